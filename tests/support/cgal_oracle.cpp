// The only translation unit that includes CGAL's triangulation headers.
#include "support/cgal_oracle.hpp"

#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>
#include <unordered_map>
#include <utility>

namespace expanse::test {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using VertexBase = CGAL::Triangulation_vertex_base_with_info_2<std::int32_t, Kernel>;
using Tds = CGAL::Triangulation_data_structure_2<VertexBase>;
using Delaunay = CGAL::Delaunay_triangulation_2<Kernel, Tds>;

bool lex_less(const Point2& a, const Point2& b) {
  return a.x < b.x || (a.x == b.x && a.y < b.y);
}

std::string triangle_text(const Triangle& t) {
  std::ostringstream s;
  s << "(" << t[0] << "," << t[1] << "," << t[2] << ")";
  return s.str();
}

// CGAL's filter fails on every predicate whose degree-4 terms under- or overflow, and its exact
// fallback is slow. Scaling by a power of two changes no predicate's sign; done only when exact.
double exact_scale(std::span<const Point2> points) {
  double largest = 0.0;
  for (const auto& p : points) largest = std::max({largest, std::fabs(p.x), std::fabs(p.y)});
  if (largest == 0.0) return 1.0;
  int exponent = 0;
  std::frexp(largest, &exponent);
  const double factor = std::ldexp(1.0, -exponent);
  if (factor == 0.0 || std::isinf(factor)) return 1.0;
  for (const auto& p : points)
    if ((p.x * factor) / factor != p.x || (p.y * factor) / factor != p.y) return 1.0;
  return factor;
}

}  // namespace

OracleResult cgal_delaunay(std::span<const Point2> points) {
  OracleResult result;
  const std::size_t n = points.size();
  result.representative.resize(n);

  // Sorting by (x, y, index) puts equal points together with their first occurrence in front.
  // Comparisons with == treat -0.0 and 0.0 as the same point, as CGAL would.
  std::vector<std::int32_t> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](std::int32_t a, std::int32_t b) {
    if (lex_less(points[a], points[b])) return true;
    if (lex_less(points[b], points[a])) return false;
    return a < b;
  });
  const double factor = exact_scale(points);
  std::vector<std::pair<Kernel::Point_2, std::int32_t>> unique;
  unique.reserve(n);
  for (std::size_t i = 0; i < n;) {
    std::size_t j = i;
    const std::int32_t first = order[i];
    while (j < n && points[order[j]] == points[first]) result.representative[order[j++]] = first;
    unique.emplace_back(Kernel::Point_2(points[first].x * factor, points[first].y * factor), first);
    i = j;
  }
  result.sites = unique.size();

  Delaunay dt;
  dt.insert(unique.begin(), unique.end());
  result.dimension = dt.dimension();

  if (dt.dimension() == 2) {
    result.triangles.reserve(dt.number_of_faces());
    for (auto f = dt.finite_faces_begin(); f != dt.finite_faces_end(); ++f)
      result.triangles.push_back({f->vertex(0)->info(), f->vertex(1)->info(), f->vertex(2)->info()});

    // Every hull edge, collinear sites included, is the finite edge of an infinite face
    // (inf, a, b) in CCW order; the interior lies right of a->b, so the CCW hull runs b -> a.
    std::unordered_map<std::int32_t, std::int32_t> next;
    std::int32_t start = -1;
    for (auto f : dt.all_face_handles()) {
      if (!dt.is_infinite(f)) continue;
      const int i = f->index(dt.infinite_vertex());
      const std::int32_t a = f->vertex(Delaunay::ccw(i))->info();
      const std::int32_t b = f->vertex(Delaunay::cw(i))->info();
      next[b] = a;
      if (start < 0 || b < start) start = b;
    }
    std::int32_t v = start;
    do {
      result.hull.push_back(v);
      v = next.at(v);
    } while (v != start && result.hull.size() <= next.size());
  } else {
    std::vector<std::int32_t> sites;
    for (const auto& [p, index] : unique) sites.push_back(index);
    std::sort(sites.begin(), sites.end(),
              [&](std::int32_t a, std::int32_t b) { return lex_less(points[a], points[b]); });
    result.hull = std::move(sites);
  }
  return result;
}

std::vector<TriangleNeighbors> compute_neighbors(std::span<const Triangle> triangles) {
  std::vector<TriangleNeighbors> neighbors(triangles.size(), {no_neighbor, no_neighbor, no_neighbor});
  // Directed edges grouped by origin (CSR); the twin of a->b is a short scan of b's edges.
  std::int32_t n = 0;
  for (const auto& t : triangles) n = std::max({n, t[0] + 1, t[1] + 1, t[2] + 1});
  std::vector<std::size_t> start(static_cast<std::size_t>(n) + 1, 0);
  for (const auto& t : triangles)
    for (auto v : t) ++start[v + 1];
  for (std::int32_t v = 0; v < n; ++v) start[v + 1] += start[v];
  std::vector<std::int32_t> target(start[n]);
  std::vector<std::int64_t> slot(start[n]);
  std::vector<std::size_t> fill(start.begin(), start.end() - 1);
  for (std::size_t t = 0; t < triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const std::size_t e = fill[triangles[t][(k + 1) % 3]]++;
      target[e] = triangles[t][(k + 2) % 3];
      slot[e] = static_cast<std::int64_t>(3 * t + k);
    }
  for (std::size_t t = 0; t < triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const std::int32_t a = triangles[t][(k + 1) % 3], b = triangles[t][(k + 2) % 3];
      for (std::size_t e = start[b]; e < start[b + 1]; ++e)
        if (target[e] == a) {
          neighbors[t][k] = static_cast<std::int32_t>(slot[e] / 3);
          break;
        }
    }
  return neighbors;
}

Mesh mesh_from_oracle(const OracleResult& oracle) {
  Mesh mesh;
  mesh.triangles = oracle.triangles;
  mesh.neighbors = compute_neighbors(mesh.triangles);
  mesh.hull = oracle.hull;
  mesh.representative = oracle.representative;
  mesh.stats.backend = "cgal";
  mesh.stats.input_points = oracle.representative.size();
  mesh.stats.sites = oracle.sites;
  mesh.stats.duplicates = oracle.representative.size() - oracle.sites;
  mesh.stats.hull_sites = oracle.hull.size();
  mesh.stats.triangles = oracle.triangles.size();
  return mesh;
}

std::vector<Triangle> canonical_triangles(std::span<const Triangle> triangles) {
  std::vector<Triangle> out(triangles.begin(), triangles.end());
  for (auto& t : out) {
    const int m = static_cast<int>(std::min_element(t.begin(), t.end()) - t.begin());
    t = {t[m], t[(m + 1) % 3], t[(m + 2) % 3]};
  }
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<std::int32_t> canonical_hull(std::span<const std::int32_t> hull) {
  std::vector<std::int32_t> out(hull.begin(), hull.end());
  if (!out.empty()) std::rotate(out.begin(), std::min_element(out.begin(), out.end()), out.end());
  return out;
}

Comparison compare_triangles(std::span<const Triangle> actual, std::span<const Triangle> expected) {
  const auto a = canonical_triangles(actual);
  const auto e = canonical_triangles(expected);
  Comparison result;
  if (a == e) return result;
  result.equal = false;
  std::vector<Triangle> missing, extra;
  std::set_difference(e.begin(), e.end(), a.begin(), a.end(), std::back_inserter(missing));
  std::set_difference(a.begin(), a.end(), e.begin(), e.end(), std::back_inserter(extra));
  std::ostringstream s;
  s << "triangles differ: " << a.size() << " actual, " << e.size() << " expected; "
    << missing.size() << " missing, " << extra.size() << " extra (or repeated)";
  if (missing.empty() && extra.empty()) s << "; the multisets differ by repeated triangles";
  const std::size_t show = 5;
  if (!missing.empty()) {
    s << "\n  missing:";
    for (std::size_t i = 0; i < std::min(show, missing.size()); ++i) s << " " << triangle_text(missing[i]);
  }
  if (!extra.empty()) {
    s << "\n  extra:";
    for (std::size_t i = 0; i < std::min(show, extra.size()); ++i) s << " " << triangle_text(extra[i]);
  }
  result.message = s.str();
  return result;
}

Comparison compare_hulls(std::span<const std::int32_t> actual, std::span<const std::int32_t> expected,
                         bool collinear) {
  Comparison result;
  std::vector<std::int32_t> a(actual.begin(), actual.end()), e(expected.begin(), expected.end());
  if (collinear) {
    if (a == e) return result;
    std::reverse(a.begin(), a.end());
    if (a == e) return result;
    std::reverse(a.begin(), a.end());
  } else {
    a = canonical_hull(a);
    e = canonical_hull(e);
    if (a == e) return result;
  }
  result.equal = false;
  std::ostringstream s;
  s << "hulls differ: " << a.size() << " actual sites, " << e.size() << " expected";
  auto list = [&](const char* name, const std::vector<std::int32_t>& h) {
    s << "\n  " << name << ":";
    for (std::size_t i = 0; i < std::min<std::size_t>(12, h.size()); ++i) s << " " << h[i];
    if (h.size() > 12) s << " ...";
  };
  list("actual", a);
  list("expected", e);
  result.message = s.str();
  return result;
}

}  // namespace expanse::test
