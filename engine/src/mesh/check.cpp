// The validity checker: everything it decides, it decides exactly, so a mesh it accepts is the
// Delaunay triangulation of the input under CGAL's perturbation, and one it rejects is wrong.
//
// It trusts nothing in the mesh: duplicates are found again from the points, edges are matched
// again from the triangles, and the hull is checked against the triangles' boundary.
#include "expanse/check.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

#include "predicates/predicates.hpp"

namespace expanse {
namespace {

constexpr std::size_t max_problems = 20;

class Problems {
 public:
  explicit Problems(CheckReport& report) : report_(report) {}

  // Keeps counting past the limit, so the final line says how many were left out.
  template <class... Parts>
  void add(const Parts&... parts) {
    report_.ok = false;
    ++count_;
    if (report_.problems.size() >= max_problems) return;
    std::ostringstream s;
    s.precision(17);
    (s << ... << parts);
    report_.problems.push_back(s.str());
  }
  std::size_t count() const { return count_; }
  void finish() {
    if (count_ > report_.problems.size())
      report_.problems.push_back("... and " + std::to_string(count_ - report_.problems.size()) +
                                 " more problems");
  }

 private:
  CheckReport& report_;
  std::size_t count_ = 0;
};

bool lex_less(const Point2& a, const Point2& b) {
  return a.x < b.x || (a.x == b.x && a.y < b.y);
}

std::string tri_text(const Triangle& t) {
  std::string s = "(";  // appended piece by piece: GCC 12 warns falsely on "(" + to_string(...)
  s += std::to_string(t[0]);
  s += ", ";
  s += std::to_string(t[1]);
  s += ", ";
  s += std::to_string(t[2]);
  s += ")";
  return s;
}

// Which half of the circle of directions the edge a->b points into: true for angles in
// (0, pi], false for (pi, 2 pi]. Decided by comparing coordinates, which is exact.
bool points_upward(const Point2& a, const Point2& b) {
  return b.y > a.y || (b.y == a.y && b.x < a.x);
}

// Directed edges a->b grouped by their origin a (CSR): each entry is 3 * t + k, the triangle
// t whose edge opposite slot k runs a->b. Degree ~6 makes the lookup of b->a a short scan, and
// the arrays stay small and cache-friendly for million-site meshes (no hash table).
struct EdgeIndex {
  std::vector<std::size_t> start;     // size N + 1
  std::vector<std::int32_t> target;   // b of each edge
  std::vector<std::int64_t> slot;     // 3 * t + k

  // The slot of the first directed edge a->b, or -1.
  std::int64_t find(std::int32_t a, std::int32_t b) const {
    for (std::size_t e = start[a]; e < start[a + 1]; ++e)
      if (target[e] == b) return slot[e];
    return -1;
  }
};

// The points scaled by a power of two so the largest |coordinate| lies in [0.5, 1), when that
// is exact for every point (checked by scaling back); else the points unchanged. Predicate
// signs and the lexicographic order are invariant under such a scaling, and scaled inputs
// near 1e-100 or 1e100 stay on the predicates' fast filter instead of their big-number path.
std::vector<Point2> scaled_copy(std::span<const Point2> points) {
  double largest = 0.0;
  for (const auto& p : points) largest = std::max({largest, std::fabs(p.x), std::fabs(p.y)});
  std::vector<Point2> out(points.begin(), points.end());
  if (largest == 0.0) return out;
  int exponent = 0;
  std::frexp(largest, &exponent);
  if (exponent == 0) return out;
  for (auto& p : out) {
    const Point2 q{std::ldexp(p.x, -exponent), std::ldexp(p.y, -exponent)};
    if (std::ldexp(q.x, exponent) != p.x || std::ldexp(q.y, exponent) != p.y)
      return {points.begin(), points.end()};
    p = q;
  }
  return out;
}

// check_mesh, step by step; each step adds what it finds to the report.
class MeshCheck {
 public:
  MeshCheck(std::span<const Point2> points, const Mesh& mesh, CheckReport& report)
      : points(points), mesh(mesh), tris(mesh.triangles), N(static_cast<std::int32_t>(points.size())), problems(report) {}

  void run() {
    check_representatives();
    P = scaled_copy(points);
    check_triangles();
    index_edges();
    check_edges();
    if (tris.empty()) {
      check_without_triangles();
      return;
    }
    for (std::int32_t v = 0; v < N; ++v)
      if (rep[v] == v && !used[v]) problems.add("site ", v, " is in no triangle");
    check_hull();
    check_euler();
  }

  /// Adds the count of problems left out of the report.
  void finish() { problems.finish(); }

 private:
  bool is_site(std::int32_t v) const { return v >= 0 && v < N && rep[v] == v; }

  void check_representatives() {
    // ---- duplicates, found again from the points: representative = first occurrence --------
    rep.assign(N, 0);
    {
      // Sorting copies (not indices into `points`) keeps the sort's memory access sequential.
      struct Keyed {
        Point2 p;
        std::int32_t index;
      };
      std::vector<Keyed> order(N);
      for (std::int32_t i = 0; i < N; ++i) order[i] = {points[i], i};
      std::sort(order.begin(), order.end(), [](const Keyed& a, const Keyed& b) {
        if (lex_less(a.p, b.p)) return true;
        if (lex_less(b.p, a.p)) return false;
        return a.index < b.index;
      });
      for (std::int32_t i = 0; i < N;) {
        const Keyed& first = order[i];
        std::int32_t j = i;
        while (j < N && order[j].p == first.p) rep[order[j++].index] = first.index;
        ++sites;
        i = j;
      }
    }
    if (mesh.representative.size() != points.size()) {
      problems.add("representative has ", mesh.representative.size(), " entries for ", points.size(),
                   " input points");
    } else {
      for (std::int32_t i = 0; i < N; ++i)
        if (mesh.representative[i] != rep[i])
          problems.add("representative[", i, "] is ", mesh.representative[i], ", expected ", rep[i],
                       " (first occurrence of the same point)");
    }
  }

  void check_triangles() {
    // ---- triangles: valid ids, representatives, strictly counter-clockwise -----------------
    tri_ok.assign(tris.size(), 1);
    used.assign(N, 0);
    for (std::size_t t = 0; t < tris.size(); ++t) {
      const Triangle& tri = tris[t];
      bool ids_ok = true;
      for (int k = 0; k < 3; ++k) {
        const std::int32_t v = tri[k];
        if (v < 0 || v >= N) {
          problems.add("triangle ", t, " ", tri_text(tri), ": vertex ", v, " out of range [0, ", N, ")");
          ids_ok = false;
        } else if (rep[v] != v) {
          problems.add("triangle ", t, " ", tri_text(tri), ": vertex ", v,
                       " repeats point ", rep[v], " (not a representative)");
          ids_ok = false;
        }
      }
      if (ids_ok && (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2])) {
        problems.add("triangle ", t, " ", tri_text(tri), " repeats a vertex");
        ids_ok = false;
      }
      if (!ids_ok) {
        tri_ok[t] = 0;
        continue;
      }
      for (int k = 0; k < 3; ++k) used[tri[k]] = 1;
      const int o = detail::orient2d(P[tri[0]], P[tri[1]], P[tri[2]]);
      if (o <= 0) {
        problems.add("triangle ", t, " ", tri_text(tri), o < 0 ? " is clockwise" : " is degenerate (collinear)");
        tri_ok[t] = 0;
      }
    }
  }

  void index_edges() {
    // ---- directed edges: each at most once; twins give neighbours and the Delaunay test --------
    edges.start.assign(static_cast<std::size_t>(N) + 1, 0);
    for (std::size_t t = 0; t < tris.size(); ++t)
      if (tri_ok[t])
        for (int k = 0; k < 3; ++k) ++edges.start[tris[t][(k + 1) % 3] + 1];
    for (std::int32_t v = 0; v < N; ++v) edges.start[v + 1] += edges.start[v];
    edges.target.resize(edges.start[N]);
    edges.slot.resize(edges.start[N]);
    {
      std::vector<std::size_t> fill(edges.start.begin(), edges.start.end() - 1);
      for (std::size_t t = 0; t < tris.size(); ++t)
        if (tri_ok[t])
          for (int k = 0; k < 3; ++k) {
            const std::size_t e = fill[tris[t][(k + 1) % 3]]++;
            edges.target[e] = tris[t][(k + 2) % 3];
            edges.slot[e] = static_cast<std::int64_t>(3 * t + k);
          }
    }
  }

  void check_edges() {
    const bool have_neighbors = !mesh.neighbors.empty();
    if (have_neighbors && mesh.neighbors.size() != tris.size())
      problems.add("neighbors has ", mesh.neighbors.size(), " entries for ", tris.size(), " triangles");
    check_neighbors = have_neighbors && mesh.neighbors.size() == tris.size();

    // Boundary edges (no twin), as directed edges of the triangles: they run CCW around the hull.
    boundary_next.assign(N, -1);
    for (std::size_t t = 0; t < tris.size(); ++t) {
      for (int k = 0; k < 3; ++k) {
        if (!tri_ok[t]) {
          if (check_neighbors) {
            // Its neighbours cannot be judged, but they must at least point somewhere real.
            const std::int32_t u = mesh.neighbors[t][k];
            if (u != no_neighbor && (u < 0 || static_cast<std::size_t>(u) >= tris.size()))
              problems.add("neighbors[", t, "][", k, "] = ", u, " is not a triangle");
          }
          continue;
        }
        const std::int32_t a = tris[t][(k + 1) % 3], b = tris[t][(k + 2) % 3], c = tris[t][k];
        // Duplicated a->b: two triangles on the same side of one edge (a repeated or
        // overlapping triangle). Report it once, from the first owner.
        const std::int64_t own = edges.find(a, b);
        if (own != static_cast<std::int64_t>(3 * t + k)) {
          problems.add("edge ", a, "->", b, " is the same side of triangles ", own / 3, " ",
                       tri_text(tris[own / 3]), " and ", t, " ", tri_text(tris[t]),
                       " (repeated or overlapping triangles)");
          boundary_ok = false;
          continue;
        }
        const std::int64_t twin = edges.find(b, a);
        if (check_neighbors) {
          const std::int32_t expected = twin < 0 ? no_neighbor : static_cast<std::int32_t>(twin / 3);
          if (mesh.neighbors[t][k] != expected)
            problems.add("neighbors[", t, "][", k, "] is ", mesh.neighbors[t][k], ", expected ", expected,
                         " (across edge ", a, "-", b, " of triangle ", t, " ", tri_text(tris[t]), ")");
        }
        if (twin < 0) {
          if (boundary_next[a] >= 0) {
            problems.add("site ", a, " starts two boundary edges (", a, "->", boundary_next[a], ", ", a,
                         "->", b, "): the triangles do not cover a disc");
            boundary_ok = false;
          }
          boundary_next[a] = b;
          ++boundary_edges;
          continue;
        }
        if (a > b) continue;  // each interior edge once
        const std::int32_t d = tris[twin / 3][twin % 3];
        if (d == c) {
          problems.add("triangles ", t, " and ", twin / 3, " ", tri_text(tris[t]),
                       " and ", tri_text(tris[twin / 3]), " are the same triangle in opposite orientations");
          continue;
        }
        if (detail::incircle_perturbed(P[a], P[b], P[c], P[d]) >= 0)
          problems.add("edge ", a, "-", b, " is not locally Delaunay: site ", d, " of triangle ", twin / 3,
                       " ", tri_text(tris[twin / 3]), " lies in the (perturbed) circle of triangle ", t, " ",
                       tri_text(tris[t]));
      }
    }
  }

  void check_without_triangles() {
    const auto& hull = mesh.hull;
  // ---- every distinct site used; the degenerate inputs ---------------------------------------
  // No triangles is right only when the sites do not span a plane.
    std::vector<std::int32_t> distinct;
    for (std::int32_t i = 0; i < N; ++i)
      if (rep[i] == i) distinct.push_back(i);
    bool collinear = true;
    if (distinct.size() >= 3) {
      const Point2& p = P[distinct[0]];
      const Point2& q = P[distinct[1]];
      for (std::size_t i = 2; i < distinct.size() && collinear; ++i)
        if (detail::orient2d(p, q, P[distinct[i]]) != 0) {
          problems.add("no triangles, but sites ", distinct[0], ", ", distinct[1], ", ", distinct[i],
                       " are not collinear");
          collinear = false;
        }
    }
    if (collinear) {
      // The hull is every site, in order along the line (either direction).
      if (hull.size() != distinct.size())
        problems.add("collinear input: hull has ", hull.size(), " sites, expected all ", distinct.size());
      std::vector<char> seen(N, 0);
      for (std::size_t i = 0; i < hull.size(); ++i) {
        if (!is_site(hull[i])) {
          problems.add("hull[", i, "] = ", hull[i], " is not a site");
          continue;
        }
        if (seen[hull[i]]++) problems.add("hull site ", hull[i], " appears twice");
      }
      bool all_sites = true;
      for (auto v : hull) all_sites = all_sites && is_site(v);
      if (all_sites && hull.size() >= 3) {
        const bool forward = lex_less(points[hull[0]], points[hull[1]]);
        for (std::size_t i = 1; i < hull.size(); ++i)
          if (lex_less(points[hull[i - 1]], points[hull[i]]) != forward) {
            problems.add("collinear input: hull is not in order along the line at position ", i);
            break;
          }
      }
    }
  }

  void check_hull() {
    const auto& hull = mesh.hull;
    // ---- hull: valid sites, CCW, convex, winding once, and exactly the boundary edges --------
    if (hull.size() < 3) {
      problems.add("hull has ", hull.size(), " sites; a mesh with triangles needs at least 3");
    } else {
      bool hull_ids_ok = true;
      std::vector<char> on_hull(N, 0);
      for (std::size_t i = 0; i < hull.size(); ++i) {
        if (!is_site(hull[i])) {
          problems.add("hull[", i, "] = ", hull[i], " is not a site");
          hull_ids_ok = false;
        } else if (on_hull[hull[i]]++) {
          problems.add("hull site ", hull[i], " appears twice");
          hull_ids_ok = false;
        }
      }
      if (hull_ids_ok) {
        const std::size_t h = hull.size();
        std::size_t upward_turns = 0;  // times the edge direction enters the upper half circle
        bool any_left_turn = false;
        for (std::size_t i = 0; i < h; ++i) {
          const Point2& p = P[hull[i]];
          const Point2& q = P[hull[(i + 1) % h]];
          const Point2& r = P[hull[(i + 2) % h]];
          const int o = detail::orient2d(p, q, r);
          if (o < 0)
            problems.add("hull turns clockwise at site ", hull[(i + 1) % h], " (", hull[i], ", ",
                         hull[(i + 1) % h], ", ", hull[(i + 2) % h], ")");
          any_left_turn = any_left_turn || o > 0;
          if (!points_upward(p, q) && points_upward(q, r)) ++upward_turns;
          // A straight 'turn' that reverses direction (p, r on the same side of q) is a spike.
          if (o == 0 && lex_less(p, q) != lex_less(q, r))
            problems.add("hull doubles back at site ", hull[(i + 1) % h]);
        }
        // Left turns only, yet winding twice, is a star polygon; once is convex.
        if (any_left_turn && upward_turns != 1)
          problems.add("hull winds ", upward_turns, " times around its interior, expected once");
        if (!any_left_turn) problems.add("hull is degenerate (all its sites collinear)");

        // The hull edges are exactly the boundary edges of the triangles.
        if (boundary_ok) {
          for (std::size_t i = 0; i < h; ++i) {
            const std::int32_t a = hull[i], b = hull[(i + 1) % h];
            if (boundary_next[a] != b)
              problems.add("hull edge ", a, "->", b, " is not a boundary edge of the triangles",
                           boundary_next[a] >= 0 ? " (the boundary goes " + std::to_string(a) + "->" +
                                                       std::to_string(boundary_next[a]) + ")"
                                                 : std::string());
          }
          if (boundary_edges != h)
            problems.add("the triangles have ", boundary_edges, " boundary edges, the hull has ", h);
        }
      }
    }
  }

  void check_euler() {
    const auto& hull = mesh.hull;
    // ---- Euler: a triangulation of n sites with h on the hull has 2n - h - 2 triangles ---------
    const auto expected_triangles =
        2 * static_cast<std::int64_t>(sites) - static_cast<std::int64_t>(hull.size()) - 2;
    if (static_cast<std::int64_t>(tris.size()) != expected_triangles)
      problems.add("Euler count: ", tris.size(), " triangles, expected 2n - h - 2 = ", expected_triangles,
                   " (n = ", sites, " sites, h = ", hull.size(), " hull sites)");
  }

  std::span<const Point2> points;
  const Mesh& mesh;
  const std::vector<Triangle>& tris;
  const std::int32_t N;
  Problems problems;
  std::vector<std::int32_t> rep;  // representative = first occurrence, found again
  std::size_t sites = 0;          // distinct points
  std::vector<Point2> P;          // every predicate reads these; comparisons may read either
  std::vector<char> tri_ok;       // valid ids, representatives, strictly counter-clockwise
  std::vector<char> used;         // sites in some valid triangle
  EdgeIndex edges;                // the valid triangles' directed edges
  bool check_neighbors = false;
  std::vector<std::int32_t> boundary_next;  // boundary edges (no twin): they run CCW around the hull
  std::size_t boundary_edges = 0;
  bool boundary_ok = true;
};

}  // namespace

CheckReport check_mesh(std::span<const Point2> points, const Mesh& mesh) {
  CheckReport report;
  if (points.size() > static_cast<std::size_t>(INT32_MAX)) {
    Problems problems(report);
    problems.add("more than 2^31 - 1 input points: indices cannot be int32");
    problems.finish();
    return report;
  }
  for (std::size_t i = 0; i < points.size(); ++i)
    if (!std::isfinite(points[i].x) || !std::isfinite(points[i].y)) {
      Problems problems(report);
      problems.add("point ", i, " is not finite: the mesh cannot be checked");
      problems.finish();
      return report;
    }
  MeshCheck check(points, mesh, report);
  check.run();
  check.finish();
  return report;
}

}  // namespace expanse
