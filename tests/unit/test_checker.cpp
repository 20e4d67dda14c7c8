// The checker must catch real faults. Correct meshes come from CGAL (not from triangulate()),
// so these tests stand on their own; each fault is made by mutating a correct mesh.
#include <catch2/catch.hpp>

#include <algorithm>
#include <numeric>
#include <string>

#include "expanse/check.hpp"
#include "predicates/predicates.hpp"
#include "support/cgal_oracle.hpp"
#include "support/timing.hpp"
#include "support/test_points.hpp"

using namespace expanse;
using namespace expanse::test;

namespace {

std::string joined(const CheckReport& report) {
  std::string s;
  for (const auto& p : report.problems) s += p + "\n";
  return s;
}

bool mentions(const CheckReport& report, const std::string& word) {
  return std::any_of(report.problems.begin(), report.problems.end(),
                     [&](const std::string& p) { return p.find(word) != std::string::npos; });
}

struct Fixture {
  std::vector<Point2> points;
  Mesh mesh;
};

Fixture correct(std::vector<Point2> points) {
  Fixture f{std::move(points), {}};
  f.mesh = mesh_from_oracle(cgal_delaunay(f.points));
  return f;
}

// An interior edge (t, k) whose two triangles form a convex quadrilateral, so flipping it
// gives two CCW triangles; returns false if there is none.
struct Flippable {
  std::size_t t, u;
  int k, l;
};
std::vector<Flippable> flippable_edges(const Fixture& f) {
  std::vector<Flippable> out;
  const auto& tris = f.mesh.triangles;
  for (std::size_t t = 0; t < tris.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const std::int32_t u = f.mesh.neighbors[t][k];
      if (u == no_neighbor || static_cast<std::size_t>(u) < t) continue;
      const auto a = tris[t][(k + 1) % 3], b = tris[t][(k + 2) % 3], c = tris[t][k];
      int l = 0;
      while (tris[u][l] == a || tris[u][l] == b) ++l;
      const auto d = tris[u][l];
      const auto& P = f.points;
      if (detail::orient2d(P[a], P[d], P[c]) > 0 && detail::orient2d(P[d], P[b], P[c]) > 0)
        out.push_back({t, static_cast<std::size_t>(u), k, l});
    }
  return out;
}

void flip(Fixture& f, const Flippable& e) {
  auto& tris = f.mesh.triangles;
  const auto a = tris[e.t][(e.k + 1) % 3], b = tris[e.t][(e.k + 2) % 3], c = tris[e.t][e.k];
  const auto d = tris[e.u][e.l];
  tris[e.t] = {a, d, c};
  tris[e.u] = {d, b, c};
  f.mesh.neighbors = compute_neighbors(tris);  // consistent, so only the Delaunay test can fail
}

}  // namespace

TEST_CASE("checker accepts CGAL's triangulation of every family", "[checker]") {
  for (const auto& family : families()) {
    for (std::size_t n : {3, 4, 10, 100, 1000}) {
      if (n > family.max_n) continue;
      const auto f = correct(family.generate(n, 7));
      const auto report = check_mesh(f.points, f.mesh);
      INFO(family.name << " n=" << n << "\n" << joined(report));
      CHECK(report.ok);
      CHECK(report.problems.empty());
    }
  }
}

TEST_CASE("checker: a flipped edge is not locally Delaunay", "[checker]") {
  SECTION("random points") {
    auto f = correct(points::uniform(200, 1));
    const auto edges = flippable_edges(f);
    REQUIRE(edges.size() > 10);
    for (std::size_t i = 0; i < edges.size(); i += edges.size() / 10) {
      auto g = f;
      flip(g, edges[i]);
      const auto report = check_mesh(g.points, g.mesh);
      INFO(joined(report));
      CHECK_FALSE(report.ok);
      CHECK(mentions(report, "not locally Delaunay"));
    }
  }
  SECTION("cocircular grid: only the perturbation tells the diagonals apart") {
    // Each unit square of a grid is cocircular; exactly one diagonal is CGAL's. The flipped
    // one passes the plain incircle test (0) and must fail the perturbed one.
    auto f = correct(points::grid(36, 3));
    const auto edges = flippable_edges(f);
    REQUIRE(!edges.empty());
    std::size_t cocircular = 0;
    for (const auto& e : edges) {
      auto g = f;
      flip(g, e);
      const auto& t = f.mesh.triangles[e.t];
      const auto d = f.mesh.triangles[e.u][e.l];
      if (detail::incircle(f.points[t[0]], f.points[t[1]], f.points[t[2]], f.points[d]) == 0) ++cocircular;
      const auto report = check_mesh(g.points, g.mesh);
      INFO(joined(report));
      CHECK_FALSE(report.ok);
      CHECK(mentions(report, "not locally Delaunay"));
    }
    CHECK(cocircular > 0);
  }
}

TEST_CASE("checker: a clockwise triangle", "[checker]") {
  auto f = correct(points::uniform(100, 2));
  std::swap(f.mesh.triangles[17][0], f.mesh.triangles[17][1]);
  f.mesh.neighbors = compute_neighbors(f.mesh.triangles);
  const auto report = check_mesh(f.points, f.mesh);
  INFO(joined(report));
  CHECK_FALSE(report.ok);
  CHECK(mentions(report, "clockwise"));
}

TEST_CASE("checker: a degenerate triangle", "[checker]") {
  // Collinear grid sites 0-1-2 in a row form a zero-area triangle.
  std::vector<Point2> p = {{0, 0}, {1, 0}, {2, 0}, {1, 1}};
  Fixture f{p, {}};
  f.mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  f.mesh.hull = {0, 1, 2, 3};
  f.mesh.representative = {0, 1, 2, 3};
  const auto report = check_mesh(f.points, f.mesh);
  INFO(joined(report));
  CHECK_FALSE(report.ok);
  CHECK(mentions(report, "degenerate"));
}

TEST_CASE("checker: a missing triangle", "[checker]") {
  auto f = correct(points::uniform(100, 3));
  SECTION("interior triangle removed") {
    // Pick a triangle with no hull edge: the hole shows only in the Euler count and boundary.
    std::size_t t = 0;
    while (std::count(f.mesh.neighbors[t].begin(), f.mesh.neighbors[t].end(), no_neighbor) > 0) ++t;
    f.mesh.triangles.erase(f.mesh.triangles.begin() + static_cast<std::ptrdiff_t>(t));
    f.mesh.neighbors = compute_neighbors(f.mesh.triangles);
    const auto report = check_mesh(f.points, f.mesh);
    INFO(joined(report));
    CHECK_FALSE(report.ok);
    CHECK(mentions(report, "Euler"));
  }
  SECTION("all triangles of one site removed") {
    const std::int32_t v = f.mesh.triangles[0][0];
    std::erase_if(f.mesh.triangles, [&](const Triangle& t) { return t[0] == v || t[1] == v || t[2] == v; });
    f.mesh.neighbors = compute_neighbors(f.mesh.triangles);
    const auto report = check_mesh(f.points, f.mesh);
    INFO(joined(report));
    CHECK_FALSE(report.ok);
    CHECK(mentions(report, "in no triangle"));
  }
}

TEST_CASE("checker: a duplicated triangle", "[checker]") {
  auto f = correct(points::uniform(100, 4));
  SECTION("same rotation") { f.mesh.triangles.push_back(f.mesh.triangles[5]); }
  SECTION("rotated copy") {
    const auto t = f.mesh.triangles[5];
    f.mesh.triangles.push_back({t[1], t[2], t[0]});
  }
  SECTION("reversed copy (covers the same area backwards)") {
    const auto t = f.mesh.triangles[5];
    f.mesh.triangles.push_back({t[1], t[0], t[2]});
  }
  f.mesh.neighbors = compute_neighbors(f.mesh.triangles);
  const auto report = check_mesh(f.points, f.mesh);
  INFO(joined(report));
  CHECK_FALSE(report.ok);
}

TEST_CASE("checker: wrong neighbors", "[checker]") {
  auto f = correct(points::uniform(100, 5));
  std::size_t interior = 0;
  while (f.mesh.neighbors[interior][0] == no_neighbor) ++interior;
  std::size_t hull_tri = 0;
  while (std::count(f.mesh.neighbors[hull_tri].begin(), f.mesh.neighbors[hull_tri].end(), no_neighbor) == 0)
    ++hull_tri;
  SECTION("interior edge claims the hull") { f.mesh.neighbors[interior][0] = no_neighbor; }
  SECTION("hull edge claims a neighbour") {
    auto& nb = f.mesh.neighbors[hull_tri];
    *std::find(nb.begin(), nb.end(), no_neighbor) = static_cast<std::int32_t>(interior);
  }
  SECTION("two slots swapped") { std::swap(f.mesh.neighbors[interior][0], f.mesh.neighbors[interior][1]); }
  SECTION("one-sided link") {
    // u forgets interior and names some third triangle instead.
    const auto u = f.mesh.neighbors[interior][0];
    std::int32_t w = 0;
    while (w == u || w == static_cast<std::int32_t>(interior)) ++w;
    for (auto& x : f.mesh.neighbors[u])
      if (x == static_cast<std::int32_t>(interior)) x = w;
  }
  SECTION("out of range") { f.mesh.neighbors[interior][2] = static_cast<std::int32_t>(f.mesh.triangles.size()); }
  SECTION("wrong length") { f.mesh.neighbors.pop_back(); }
  const auto report = check_mesh(f.points, f.mesh);
  INFO(joined(report));
  CHECK_FALSE(report.ok);
  CHECK(mentions(report, "neighbors"));
}

TEST_CASE("checker: empty neighbors are allowed (Options::neighbors = false)", "[checker]") {
  auto f = correct(points::uniform(100, 5));
  f.mesh.neighbors.clear();
  CHECK(check_mesh(f.points, f.mesh).ok);
}

TEST_CASE("checker: wrong hull", "[checker]") {
  // A grid has collinear hull sites: dropping one of them must be caught too.
  auto f = correct(points::grid(25, 6));
  REQUIRE(f.mesh.hull.size() == 16);
  SECTION("rotated hull is still right") {
    std::rotate(f.mesh.hull.begin(), f.mesh.hull.begin() + 5, f.mesh.hull.end());
    CHECK(check_mesh(f.points, f.mesh).ok);
    return;
  }
  SECTION("collinear hull site left out") {
    // The grid's corners turn; the others are collinear. Remove a collinear one.
    const auto& h = f.mesh.hull;
    std::size_t i = 0;
    while (detail::orient2d(f.points[h[(i + h.size() - 1) % h.size()]], f.points[h[i]],
                            f.points[h[(i + 1) % h.size()]]) != 0)
      ++i;
    f.mesh.hull.erase(f.mesh.hull.begin() + static_cast<std::ptrdiff_t>(i));
  }
  SECTION("clockwise") { std::reverse(f.mesh.hull.begin(), f.mesh.hull.end()); }
  SECTION("two sites swapped") { std::swap(f.mesh.hull[3], f.mesh.hull[4]); }
  SECTION("an interior site added") {
    for (std::int32_t v = 0; v < 25; ++v)
      if (std::find(f.mesh.hull.begin(), f.mesh.hull.end(), v) == f.mesh.hull.end()) {
        f.mesh.hull.insert(f.mesh.hull.begin() + 2, v);
        break;
      }
  }
  SECTION("a site repeated") { f.mesh.hull.push_back(f.mesh.hull[0]); }
  SECTION("traversed twice") {
    const auto h = f.mesh.hull;
    f.mesh.hull.insert(f.mesh.hull.end(), h.begin(), h.end());
  }
  SECTION("empty") { f.mesh.hull.clear(); }
  const auto report = check_mesh(f.points, f.mesh);
  INFO(joined(report));
  CHECK_FALSE(report.ok);
  CHECK(mentions(report, "hull"));
}

TEST_CASE("checker: duplicates and representatives", "[checker]") {
  // Point 3 repeats point 1; point 5 repeats point 0.
  std::vector<Point2> p = {{0, 0}, {1, 0}, {0, 1}, {1, 0}, {1, 1}, {0, 0}};
  auto f = correct(p);
  REQUIRE(f.mesh.representative == std::vector<std::int32_t>{0, 1, 2, 1, 4, 0});
  REQUIRE(check_mesh(f.points, f.mesh).ok);
  SECTION("later copy used as a vertex") {
    for (auto& t : f.mesh.triangles)
      for (auto& v : t)
        if (v == 1) v = 3;
    const auto report = check_mesh(f.points, f.mesh);
    INFO(joined(report));
    CHECK_FALSE(report.ok);
    CHECK(mentions(report, "not a representative"));
  }
  SECTION("representative map points to the last copy") {
    f.mesh.representative[1] = 3;
    f.mesh.representative[3] = 3;
    const auto report = check_mesh(f.points, f.mesh);
    CHECK_FALSE(report.ok);
    CHECK(mentions(report, "representative"));
  }
  SECTION("representative map missing") {
    f.mesh.representative.clear();
    CHECK_FALSE(check_mesh(f.points, f.mesh).ok);
  }
}

TEST_CASE("checker: degenerate inputs", "[checker]") {
  SECTION("collinear sites, no triangles") {
    auto f = correct(points::collinear_plus_one(8, 1));
    // Drop the off-line point: what remains is collinear.
    std::vector<Point2> line;
    for (const auto& q : f.points)
      if (q.y == 3 * q.x + 1) line.push_back(q);
    auto g = correct(line);
    REQUIRE(g.mesh.triangles.empty());
    CHECK(check_mesh(g.points, g.mesh).ok);
    std::reverse(g.mesh.hull.begin(), g.mesh.hull.end());
    CHECK(check_mesh(g.points, g.mesh).ok);  // either direction along the line
    std::swap(g.mesh.hull[0], g.mesh.hull[3]);
    CHECK_FALSE(check_mesh(g.points, g.mesh).ok);
    g.mesh.hull.pop_back();
    CHECK_FALSE(check_mesh(g.points, g.mesh).ok);
  }
  SECTION("non-collinear sites without triangles") {
    auto f = correct(points::uniform(10, 1));
    f.mesh.triangles.clear();
    f.mesh.neighbors.clear();
    const auto report = check_mesh(f.points, f.mesh);
    CHECK_FALSE(report.ok);
    CHECK(mentions(report, "not collinear"));
  }
  SECTION("no points") {
    Fixture f = correct({});
    CHECK(check_mesh(f.points, f.mesh).ok);
  }
  SECTION("vertex out of range") {
    auto f = correct(points::uniform(10, 1));
    f.mesh.triangles[0][1] = 10;
    const auto report = check_mesh(f.points, f.mesh);
    CHECK_FALSE(report.ok);
    CHECK(mentions(report, "out of range"));
  }
}

TEST_CASE("checker: problem list is bounded", "[checker]") {
  auto f = correct(points::uniform(2000, 9));
  for (auto& t : f.mesh.triangles) std::swap(t[0], t[1]);
  const auto report = check_mesh(f.points, f.mesh);
  CHECK_FALSE(report.ok);
  CHECK(report.problems.size() <= 21);
  CHECK(report.problems.back().find("more problems") != std::string::npos);
}

TEST_CASE("checker: one million sites in reasonable time", "[checker][.slow]") {
  auto f = correct(points::uniform(1000000, 11));
  const expanse::detail::Stopwatch timer;
  const auto report = check_mesh(f.points, f.mesh);
  WARN("check_mesh on 1M sites: " << timer.ms() / 1000 << " s");
  CHECK(report.ok);
}

TEST_CASE("oracle: comparison helpers see real differences only", "[oracle]") {
  const std::vector<Triangle> mesh = {{0, 1, 2}, {2, 1, 3}, {4, 2, 3}};
  SECTION("order and rotation do not matter") {
    const std::vector<Triangle> same = {{1, 3, 2}, {3, 4, 2}, {2, 0, 1}};
    CHECK(compare_triangles(same, mesh).equal);
  }
  SECTION("orientation matters") {
    const std::vector<Triangle> reversed = {{0, 2, 1}, {2, 1, 3}, {4, 2, 3}};
    const auto c = compare_triangles(reversed, mesh);
    CHECK_FALSE(c.equal);
    CHECK(c.message.find("1 missing, 1 extra") != std::string::npos);
  }
  SECTION("a repeated triangle is a difference") {
    auto repeated = mesh;
    repeated.push_back(mesh[1]);
    CHECK_FALSE(compare_triangles(repeated, mesh).equal);
  }
  SECTION("a missing triangle is a difference") {
    const std::vector<Triangle> fewer(mesh.begin(), mesh.end() - 1);
    CHECK_FALSE(compare_triangles(fewer, mesh).equal);
  }
  SECTION("hulls compare as cycles, collinear ones as lines in either direction") {
    const std::vector<std::int32_t> hull = {4, 0, 1, 3};
    CHECK(compare_hulls(std::vector<std::int32_t>{1, 3, 4, 0}, hull, false).equal);
    CHECK_FALSE(compare_hulls(std::vector<std::int32_t>{0, 4, 3, 1}, hull, false).equal);  // clockwise
    CHECK_FALSE(compare_hulls(std::vector<std::int32_t>{4, 0, 1}, hull, false).equal);
    CHECK(compare_hulls(std::vector<std::int32_t>{3, 1, 0, 4}, hull, true).equal);
    CHECK_FALSE(compare_hulls(std::vector<std::int32_t>{1, 3, 4, 0}, hull, true).equal);
  }
}

TEST_CASE("oracle: duplicates keep their first occurrence, the hull keeps collinear sites", "[oracle]") {
  // A 3x3 grid listed twice in reverse, so CGAL's spatial sort sees the later copies too.
  std::vector<Point2> p;
  for (int i = 8; i >= 0; --i) p.push_back({static_cast<double>(i % 3), static_cast<double>(i / 3)});
  for (int i = 8; i >= 0; --i) p.push_back({static_cast<double>(i % 3), static_cast<double>(i / 3)});
  const auto oracle = cgal_delaunay(p);
  CHECK(oracle.sites == 9);
  for (std::int32_t i = 0; i < 18; ++i) CHECK(oracle.representative[i] == i % 9);
  for (const auto& t : oracle.triangles)
    for (auto v : t) CHECK(v < 9);
  CHECK(oracle.triangles.size() == 8);
  // Corners (2,2) (0,2) (0,0) (2,0) are inputs 0, 2, 8, 6; the edge midpoints are on the hull too.
  CHECK(canonical_hull(oracle.hull) == std::vector<std::int32_t>{0, 1, 2, 5, 8, 7, 6, 3});
}
