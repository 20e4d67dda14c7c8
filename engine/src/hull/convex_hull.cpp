#include "hull/convex_hull.hpp"

#include <algorithm>
#include <array>
#include <limits>

#include "input/parallel.hpp"
#include "predicates/predicates.hpp"

namespace expanse::detail {
namespace {

bool lex_less(const Point2& p, const Point2& q) { return p.x < q.x || (p.x == q.x && p.y < q.y); }

// Akl–Toussaint: sites strictly inside the polygon of the eight extreme sites cannot be on the
// hull (not even as collinear hull sites), so only the rest need sorting.
std::vector<std::int32_t> hull_candidates(const SiteSet& sites) {
  const auto& p = sites.points;
  const std::int32_t n = sites.size();
  // Extremes in 8 directions, in CCW order: min y, min (y - x)... expressed as maximisers of
  // direction dot products; exact ties do not matter for correctness.
  // Directions: (0, -1), (1, -1), (1, 0), (1, 1), (0, 1), (-1, 1), (-1, 0), (-1, -1).
  // Per chunk, then over chunks in order: the first site with the largest value, as one pass.
  struct Extremes {
    std::array<std::int32_t, 8> site{};
    std::array<double, 8> best{};
  };
  const std::size_t chunks = chunk_count(static_cast<std::size_t>(n));
  std::vector<Extremes> found(chunks);
  // direction d . p[i], each rounded as the dot product is (0 * x adds a zero; rounding to
  // nearest is symmetric, so -x - y == -(x + y) and -x + y == -(x - y)).
  const auto value = [&](std::size_t i, int d) {
    const double x = p[i].x, y = p[i].y;
    switch (d) {
      case 0: return -y;
      case 1: return x - y;
      case 2: return x;
      case 3: return x + y;
      case 4: return y;
      case 5: return -(x - y);
      case 6: return -x;
      default: return -(x + y);
    }
  };
  parallel_chunks(static_cast<std::size_t>(n), chunks, [&](std::size_t chunk, std::size_t begin, std::size_t end) {
    Extremes e;
    e.best.fill(-std::numeric_limits<double>::infinity());
    // Blocks of sites: the maxima of a block vectorise (no site to track); only a block that
    // beats the best so far, rare after the first few, is searched for its first maximal site.
    // The same site as a site-by-site scan: the first one with the largest value.
    constexpr std::size_t block = 256;
    for (std::size_t lo = begin; lo < end; lo += block) {
      const std::size_t hi = std::min(end, lo + block);
      double top[8];
      for (int d = 0; d < 8; ++d) top[d] = -std::numeric_limits<double>::infinity();
      for (std::size_t i = lo; i < hi; ++i) {
        const double x = p[i].x, y = p[i].y, sum = x + y, difference = x - y;
        const double values[8] = {-y, difference, x, sum, y, -difference, -x, -sum};
        for (int d = 0; d < 8; ++d) top[d] = values[d] > top[d] ? values[d] : top[d];
      }
      for (int d = 0; d < 8; ++d) {
        if (!(top[d] > e.best[d])) continue;
        std::size_t i = lo;
        while (value(i, d) != top[d]) ++i;
        e.best[d] = top[d];
        e.site[d] = static_cast<std::int32_t>(i);
      }
    }
    found[chunk] = e;
  });
  std::array<std::int32_t, 8> extreme{};
  std::array<double, 8> best{};
  best.fill(-std::numeric_limits<double>::infinity());
  for (const Extremes& e : found) {
    for (int d = 0; d < 8; ++d) {
      if (e.best[d] > best[d]) {
        best[d] = e.best[d];
        extreme[d] = e.site[d];
      }
    }
  }
  std::vector<std::int32_t> polygon;
  for (std::int32_t e : extreme) {
    if (polygon.empty() || (polygon.back() != e && polygon.front() != e)) polygon.push_back(e);
  }
  // The extremes are hull sites in CCW order, but rounding in the dot products could in
  // principle misorder nearly-equal ones: only use the polygon if it is strictly convex.
  const std::size_t m = polygon.size();
  bool usable = m >= 3;
  for (std::size_t k = 0; usable && k < m; ++k) {
    usable = orient2d(p[polygon[k]], p[polygon[(k + 1) % m]], p[polygon[(k + 2) % m]]) > 0;
  }
  // A box whose corners are strictly inside the polygon rejects most sites with four compares.
  double inner_x0 = 0, inner_x1 = -1, inner_y0 = 0, inner_y1 = -1;
  if (usable) {
    // extreme[] order: S, SE, E, NE, N, NW, W, SW.
    inner_x0 = std::max({p[extreme[5]].x, p[extreme[6]].x, p[extreme[7]].x});
    inner_x1 = std::min({p[extreme[1]].x, p[extreme[2]].x, p[extreme[3]].x});
    inner_y0 = std::max({p[extreme[7]].y, p[extreme[0]].y, p[extreme[1]].y});
    inner_y1 = std::min({p[extreme[3]].y, p[extreme[4]].y, p[extreme[5]].y});
    // A corner often is an extreme site itself (on the polygon, not strictly inside): pull the
    // box in a little. The corners are then checked exactly.
    const double shrink_x = 1e-6 * (inner_x1 - inner_x0), shrink_y = 1e-6 * (inner_y1 - inner_y0);
    inner_x0 += shrink_x;
    inner_x1 -= shrink_x;
    inner_y0 += shrink_y;
    inner_y1 -= shrink_y;
    for (const Point2& corner : {Point2{inner_x0, inner_y0}, Point2{inner_x1, inner_y0}, Point2{inner_x1, inner_y1},
                                 Point2{inner_x0, inner_y1}}) {
      for (std::size_t k = 0; k < m; ++k) {
        if (orient2d(p[polygon[k]], p[polygon[(k + 1) % m]], corner) <= 0) inner_x1 = inner_x0 - 1;  // unusable
      }
    }
  }
  // Per chunk, concatenated in chunk order: the sites in increasing order, as one pass.
  std::vector<std::vector<std::int32_t>> kept(chunks);
  parallel_chunks(static_cast<std::size_t>(n), chunks, [&](std::size_t chunk, std::size_t begin, std::size_t end) {
    auto& mine = kept[chunk];
    if (!usable) mine.reserve(end - begin);
    for (std::size_t i = begin; i < end; ++i) {
      if (p[i].x > inner_x0 && p[i].x < inner_x1 && p[i].y > inner_y0 && p[i].y < inner_y1) continue;
      bool strictly_inside = usable;
      for (std::size_t k = 0; strictly_inside && k < m; ++k) {
        strictly_inside = orient2d(p[polygon[k]], p[polygon[(k + 1) % m]], p[i]) > 0;
      }
      if (!strictly_inside) mine.push_back(static_cast<std::int32_t>(i));
    }
  });
  if (chunks == 1) return std::move(kept[0]);
  std::vector<std::int32_t> candidates;
  std::size_t total = 0;
  for (const auto& part : kept) total += part.size();
  candidates.reserve(total);
  for (const auto& part : kept) candidates.insert(candidates.end(), part.begin(), part.end());
  return candidates;
}

}  // namespace

Hull convex_hull(const SiteSet& sites) {
  const auto& p = sites.points;
  Hull hull;
  resize_for_parallel_write(hull.predecessor, p.size());
  parallel_chunks(p.size(), [&](std::size_t, std::size_t begin, std::size_t end) {
    std::fill(hull.predecessor.begin() + static_cast<std::ptrdiff_t>(begin),
              hull.predecessor.begin() + static_cast<std::ptrdiff_t>(end), -1);
  });
  if (p.empty()) return hull;

  std::vector<std::int32_t> order = hull_candidates(sites);
  std::sort(order.begin(), order.end(),
            [&](std::int32_t a, std::int32_t b) { return lex_less(p[a], p[b]); });

  const std::int32_t first = order.front();
  const std::int32_t last = order.back();
  hull.collinear = std::all_of(order.begin(), order.end(), [&](std::int32_t i) {
    return orient2d(p[first], p[last], p[i]) == 0;
  });
  if (hull.collinear) {
    // Every site is a candidate here (nothing is strictly inside a degenerate polygon).
    hull.sites = order;
    return hull;
  }

  // Monotone chain that keeps collinear sites: pop only on a strict right turn. The lower chain
  // takes the right vertical side, the upper chain the left one, so nothing is listed twice.
  std::vector<std::int32_t> chain;
  chain.reserve(order.size() + 1);
  auto extend = [&](std::int32_t site, std::size_t floor) {
    while (chain.size() >= floor + 2 &&
           orient2d(p[chain[chain.size() - 2]], p[chain.back()], p[site]) < 0) {
      chain.pop_back();
    }
    chain.push_back(site);
  };
  for (std::int32_t site : order) extend(site, 0);
  const std::size_t lower_size = chain.size();
  for (auto it = order.rbegin() + 1; it != order.rend(); ++it) extend(*it, lower_size - 1);
  chain.pop_back();  // the first site again

  hull.sites = std::move(chain);
  const std::size_t h = hull.sites.size();
  for (std::size_t k = 0; k < h; ++k) hull.predecessor[hull.sites[k]] = hull.sites[(k + h - 1) % h];
  return hull;
}

}  // namespace expanse::detail
