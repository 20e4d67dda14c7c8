// convex_hull() drops sites that are certainly strictly inside the polygon of its eight extreme
// sites before the monotone chain (an inner box, a grid of cells inside the polygon, the
// orientation filter, then exact tests). Whatever path a site takes, the hull must equal the
// monotone chain over every site, collinear hull sites included.
#include <catch2/catch.hpp>

#include <algorithm>
#include <numeric>
#include <string>

#include "expanse/generate.hpp"
#include "hull/convex_hull.hpp"
#include "input/parallel.hpp"
#include "input/site_set.hpp"
#include "predicates/predicates.hpp"

using namespace expanse;
using namespace expanse::detail;

namespace {

struct Threads {
  explicit Threads(std::size_t n) { set_host_threads(n); }
  ~Threads() { set_host_threads(0); }
};

// The monotone chain over all sites, no filter: pop only on a strict right turn.
std::vector<std::int32_t> reference_hull(const SiteSet& sites, bool& collinear) {
  const auto& p = sites.points;
  std::vector<std::int32_t> order(p.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](std::int32_t a, std::int32_t b) {
    return p[a].x < p[b].x || (p[a].x == p[b].x && p[a].y < p[b].y);
  });
  collinear = std::all_of(order.begin(), order.end(),
                          [&](std::int32_t i) { return orient2d(p[order.front()], p[order.back()], p[i]) == 0; });
  if (collinear) return order;
  std::vector<std::int32_t> chain;
  const auto extend = [&](std::int32_t site, std::size_t floor) {
    while (chain.size() >= floor + 2 && orient2d(p[chain[chain.size() - 2]], p[chain.back()], p[site]) < 0) {
      chain.pop_back();
    }
    chain.push_back(site);
  };
  for (std::int32_t site : order) extend(site, 0);
  const std::size_t lower = chain.size();
  for (auto it = order.rbegin() + 1; it != order.rend(); ++it) extend(*it, lower - 1);
  chain.pop_back();
  return chain;
}

void check_hull(const std::vector<Point2>& points) {
  const SiteSet sites = prepare_sites(points);
  bool collinear = false;
  const std::vector<std::int32_t> expected = reference_hull(sites, collinear);
  for (std::size_t threads : {1, 2, 7}) {
    INFO(threads << " threads");
    Threads use(threads);
    const Hull hull = convex_hull(sites);
    CHECK(hull.collinear == collinear);
    CHECK(hull.sites == expected);
    if (collinear) continue;
    std::vector<std::int32_t> predecessor(static_cast<std::size_t>(sites.size()), -1);
    for (std::size_t k = 0; k < expected.size(); ++k) {
      predecessor[expected[k]] = expected[(k + expected.size() - 1) % expected.size()];
    }
    CHECK(std::equal(hull.predecessor.begin(), hull.predecessor.end(), predecessor.begin(), predecessor.end()));
  }
}

}  // namespace

TEST_CASE("hull: the monotone chain over every site, for every distribution", "[hull]") {
  for (const char* distribution : {"uniform", "gaussian", "clusters", "grid", "rotated_grid", "circle", "disk",
                                   "kuzmin", "line", "collinear_plus_one", "duplicates", "offset", "near_collinear",
                                   "thin_circle", "tiny", "huge"}) {
    for (std::size_t n : {std::size_t{1000}, std::size_t{300000}}) {
      INFO(distribution << ", n = " << n);
      check_hull(generate_points(distribution, n, 5));
    }
  }
}

TEST_CASE("hull: lattice bands whose sides are full of collinear hull sites (the grid filter's path)", "[hull]") {
  // A diagonal band of integer points: the box of the extremes is tiny, so the cells inside the
  // polygon do the filtering, and many sites lie exactly on hull edges near those cells.
  std::vector<Point2> band;
  for (int x = 0; x <= 3000; ++x) {
    for (int y = x - 40; y <= x + 40; ++y) band.push_back({static_cast<double>(x), static_cast<double>(y)});
  }
  check_hull(band);
  // Two diagonal clusters far apart, joined by a sparse line of points on the diagonal.
  std::vector<Point2> clusters;
  for (int cluster = 0; cluster < 2; ++cluster) {
    const int c = cluster * 5000;
    for (int x = -150; x <= 150; ++x) {
      for (int y = -150; y <= 150; ++y) {
        if (x * x + y * y <= 150 * 150) clusters.push_back({static_cast<double>(c + x), static_cast<double>(c + y)});
      }
    }
  }
  for (int t = 0; t <= 5000; t += 7) clusters.push_back({static_cast<double>(t), static_cast<double>(t)});
  check_hull(clusters);
}
