// orient2d / incircle / incircle_perturbed against an independent exact reference (GMP
// rationals) on random and adversarial inputs, and the perturbation against CGAL itself.
// This is the one unit-test file that includes CGAL.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <random>
#include <set>
#include <string>
#include <vector>

#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <catch2/catch.hpp>
#include <gmpxx.h>

#include "predicates/predicates.hpp"

using expanse::Point2;
namespace detail = expanse::detail;

namespace {

// ---- Reference: the determinants in rationals, written independently of the library --------

int reference_orient2d(const Point2& a, const Point2& b, const Point2& c) {
  const mpq_class ax(a.x), ay(a.y), bx(b.x), by(b.y), cx(c.x), cy(c.y);
  return sgn((bx - ax) * (cy - ay) - (by - ay) * (cx - ax));
}

int reference_incircle(const Point2& a, const Point2& b, const Point2& c, const Point2& d) {
  // The 4x4 lifted determinant, expanded along the lift column about the origin.
  const Point2* p[4] = {&a, &b, &c, &d};
  mpq_class x[4], y[4], lift[4];
  for (int i = 0; i < 4; ++i) {
    x[i] = p[i]->x;
    y[i] = p[i]->y;
    lift[i] = x[i] * x[i] + y[i] * y[i];
  }
  // det | x y lift 1 | for rows a, b, c, d, via 3x3 minors.
  auto minor3 = [&](int i, int j, int k) -> mpq_class {  // not an expression template: those dangle
    return x[i] * (y[j] - y[k]) - y[i] * (x[j] - x[k]) + (x[j] * y[k] - x[k] * y[j]);
  };
  // Cofactor expansion along the lift column (column 2): sign pattern for rows 0..3 is
  // +,-,+,- times (-1)^(2) ... computed directly to avoid sign slips:
  const mpq_class det = -lift[0] * minor3(1, 2, 3) + lift[1] * minor3(0, 2, 3) -
                        lift[2] * minor3(0, 1, 3) + lift[3] * minor3(0, 1, 2);
  // The standard incircle determinant (d inside CCW abc > 0) is minus this row ordering.
  return -sgn(det);
}

// ---- Input generators ------------------------------------------------------------------------

struct Rng {
  std::mt19937_64 engine;
  explicit Rng(std::uint64_t seed) : engine(seed) {}
  double uniform(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(engine); }
  int integer(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(engine); }
  Point2 point(double lo, double hi) { return {uniform(lo, hi), uniform(lo, hi)}; }
  double nudge(double v, int max_ulps) {
    const int steps = integer(-max_ulps, max_ulps);
    for (int i = 0; i < std::abs(steps); ++i)
      v = std::nextafter(v, steps > 0 ? INFINITY : -INFINITY);
    return v;
  }
  Point2 nudge(Point2 p, int max_ulps) { return {nudge(p.x, max_ulps), nudge(p.y, max_ulps)}; }
  /// A double with random mantissa and an exponent anywhere from subnormal to huge.
  double any_magnitude(int min_exponent, int max_exponent) {
    const double mantissa = uniform(1.0, 2.0) * (integer(0, 1) ? 1.0 : -1.0);
    return std::ldexp(mantissa, integer(min_exponent, max_exponent));
  }
};

Point2 scaled(Point2 p, double factor) { return {p.x * factor, p.y * factor}; }
Point2 shifted(Point2 p, Point2 by) { return {p.x + by.x, p.y + by.y}; }

/// The rounded point a fraction t of the way from a to b: almost, rarely exactly, collinear.
Point2 along(const Point2& a, const Point2& b, double t) {
  return {a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)};
}

/// All integer points on x^2 + y^2 = r2.
std::vector<Point2> integer_circle(long r2) {
  std::vector<Point2> points;
  const long r = static_cast<long>(std::sqrt(double(r2))) + 1;
  for (long x = -r; x <= r; ++x)
    for (long y = -r; y <= r; ++y)
      if (x * x + y * y == r2) points.push_back({double(x), double(y)});
  // Counter-clockwise by angle, so consecutive triples are CCW.
  std::sort(points.begin(), points.end(), [](const Point2& p, const Point2& q) {
    return std::atan2(p.y, p.x) < std::atan2(q.y, q.x);
  });
  return points;
}

struct Counts {
  long orient = 0, incircle = 0, zero_orient = 0, zero_incircle = 0;
};

void check_orient(const Point2& a, const Point2& b, const Point2& c, Counts& counts) {
  const int expected = reference_orient2d(a, b, c);
  // Every cyclic rotation and reflection must agree with the reference too.
  const int got = detail::orient2d(a, b, c);
  if (got != expected) {
    INFO("orient2d(" << a.x << "," << a.y << " | " << b.x << "," << b.y << " | " << c.x << ","
                     << c.y << ")");
    REQUIRE(got == expected);
  }
  REQUIRE(detail::orient2d(b, c, a) == expected);
  REQUIRE(detail::orient2d(b, a, c) == -expected);
  ++counts.orient;
  counts.zero_orient += expected == 0;
}

void check_incircle(const Point2& a, const Point2& b, const Point2& c, const Point2& d,
                    Counts& counts) {
  const int expected = reference_incircle(a, b, c, d);
  const int got = detail::incircle(a, b, c, d);
  if (got != expected) {
    INFO("incircle(" << a.x << "," << a.y << " | " << b.x << "," << b.y << " | " << c.x << ","
                     << c.y << " | " << d.x << "," << d.y << ")");
    REQUIRE(got == expected);
  }
  REQUIRE(detail::incircle(b, c, a, d) == expected);
  REQUIRE(detail::incircle(b, a, c, d) == -expected);
  ++counts.incircle;
  counts.zero_incircle += expected == 0;
}

/// Runs `make` n times; each call produces four points that are checked with every predicate.
void check_family(int n, std::uint64_t seed, const std::function<std::array<Point2, 4>(Rng&)>& make,
                  Counts& counts) {
  Rng rng(seed);
  for (int i = 0; i < n; ++i) {
    const auto p = make(rng);
    check_orient(p[0], p[1], p[2], counts);
    check_orient(p[0], p[1], p[3], counts);
    check_incircle(p[0], p[1], p[2], p[3], counts);
  }
}

}  // namespace

TEST_CASE("reference determinants agree with textbook cases", "[predicates]") {
  const Point2 o{0, 0}, x{1, 0}, y{0, 1}, far{5, 5}, mid{0.25, 0.25}, diag{1, 1};
  CHECK(reference_orient2d(o, x, y) == 1);
  CHECK(reference_incircle(o, x, y, mid) == 1);
  CHECK(reference_incircle(o, x, y, far) == -1);
  CHECK(reference_incircle(o, x, y, diag) == 0);
}

TEST_CASE("random points", "[predicates]") {
  Counts counts;
  check_family(5000, 1, [](Rng& r) -> std::array<Point2, 4> {
    return {r.point(-1, 1), r.point(-1, 1), r.point(-1, 1), r.point(-1, 1)};
  }, counts);
  check_family(2000, 2, [](Rng& r) -> std::array<Point2, 4> {
    // Small integers: many exact zeros.
    auto p = [&] { return Point2{double(r.integer(-3, 3)), double(r.integer(-3, 3))}; };
    return {p(), p(), p(), p()};
  }, counts);
  CHECK(counts.zero_orient > 100);
  CHECK(counts.zero_incircle > 100);
}

TEST_CASE("near-collinear and near-cocircular points, nudged by ulps", "[predicates]") {
  Counts counts;
  check_family(4000, 3, [](Rng& r) -> std::array<Point2, 4> {
    const Point2 a = r.point(-1, 1), b = r.point(-1, 1);
    const Point2 c = r.nudge(along(a, b, r.uniform(-2, 3)), 2);
    const Point2 d = r.nudge(along(a, b, r.uniform(-2, 3)), 1);
    return {a, b, c, d};
  }, counts);
  check_family(4000, 4, [](Rng& r) -> std::array<Point2, 4> {
    // Points on a circle, rounded, then nudged: the incircle filter almost never decides.
    const Point2 centre = r.point(-10, 10);
    const double radius = r.uniform(0.1, 10);
    auto on_circle = [&](double angle) {
      return r.nudge(Point2{centre.x + radius * std::cos(angle), centre.y + radius * std::sin(angle)}, 1);
    };
    const double t = r.uniform(0, 1);
    return {on_circle(t), on_circle(t + 2), on_circle(t + 4), on_circle(t + r.uniform(0, 6.28))};
  }, counts);
  // The classic: points on y = x near (0.5, 0.5), sweeping a grid of ulps.
  for (int i = 0; i < 64; ++i)
    for (int j = 0; j < 64; ++j) {
      Point2 p{0.5, 0.5};
      for (int k = 0; k < i; ++k) p.x = std::nextafter(p.x, 1.0);
      for (int k = 0; k < j; ++k) p.y = std::nextafter(p.y, 1.0);
      check_orient(p, {12, 12}, {24, 24}, counts);
    }
  CHECK(counts.zero_orient >= 64);
}

TEST_CASE("exactly cocircular integer points", "[predicates]") {
  Counts counts;
  for (long r2 : {25L, 50L, 65L, 325L, 1105L, 5525L, 25L * 1105L}) {
    const auto circle = integer_circle(r2);
    REQUIRE(circle.size() >= 8);
    Rng rng(r2);
    for (int i = 0; i < 1000; ++i) {
      const Point2 offset{double(rng.integer(-1000, 1000)), double(rng.integer(-1000, 1000))};
      std::array<Point2, 4> p;
      for (auto& q : p) q = shifted(circle[rng.integer(0, int(circle.size()) - 1)], offset);
      check_incircle(p[0], p[1], p[2], p[3], counts);
      check_orient(p[0], p[1], p[2], counts);
      // The same quadruple scaled by a power of two (still exact) and by 0.1 (rounded).
      const double factor = rng.integer(0, 1) ? std::ldexp(1.0, rng.integer(-60, 60)) : 0.1;
      check_incircle(scaled(p[0], factor), scaled(p[1], factor), scaled(p[2], factor),
                     scaled(p[3], factor), counts);
    }
  }
  CHECK(counts.zero_incircle > 3000);
}

TEST_CASE("large offsets with tiny spread", "[predicates]") {
  Counts counts;
  check_family(4000, 5, [](Rng& r) -> std::array<Point2, 4> {
    const Point2 base{1e8, 1e8};
    auto p = [&] { return shifted(base, r.point(-1e-6, 1e-6)); };
    const Point2 a = p(), b = p();
    return {a, b, r.nudge(along(a, b, r.uniform(-1, 2)), 1), p()};
  }, counts);
  check_family(2000, 6, [](Rng& r) -> std::array<Point2, 4> {
    // Cocircular integers shifted by 2^27: exact in doubles, degree-4 terms need 108+ bits.
    const Point2 base{134217728.0, -134217728.0};
    const auto& circle = integer_circle(1105);
    auto p = [&] { return shifted(circle[r.integer(0, int(circle.size()) - 1)], base); };
    return {p(), p(), p(), p()};
  }, counts);
  CHECK(counts.zero_incircle > 100);
}

TEST_CASE("extreme magnitudes: 1e+-100, 1e+-300, mixed, subnormal", "[predicates]") {
  Counts counts;
  for (double scale : {1e-100, 1e100, 1e-300, 1e300, 0x1p-1000, 0x1p1000}) {
    check_family(1000, 7, [scale](Rng& r) -> std::array<Point2, 4> {
      const Point2 a = scaled(r.point(-1, 1), scale), b = scaled(r.point(-1, 1), scale);
      return {a, b, r.nudge(along(a, b, r.uniform(-1, 2)), 1), scaled(r.point(-1, 1), scale)};
    }, counts);
    // Exact degeneracies survive scaling by a power of two near the same magnitude.
    const double power = std::ldexp(1.0, std::ilogb(scale));
    check_family(500, 8, [power](Rng& r) -> std::array<Point2, 4> {
      const auto& circle = integer_circle(325);
      auto p = [&] { return scaled(circle[r.integer(0, int(circle.size()) - 1)], power); };
      return {p(), p(), p(), p()};
    }, counts);
  }
  check_family(2000, 9, [](Rng& r) -> std::array<Point2, 4> {
    // Mixed: one coordinate near 1e-300, the rest of order 1.
    auto p = [&] { return r.integer(0, 3) == 0 ? r.point(-1e-300, 1e-300) : r.point(-1, 1); };
    return {p(), p(), p(), p()};
  }, counts);
  check_family(2000, 10, [](Rng& r) -> std::array<Point2, 4> {
    // Subnormal integers times 2^-1074: exact grids and circles in the subnormal range.
    auto p = [&] { return Point2{r.integer(-4, 4) * 0x1p-1074, r.integer(-4, 4) * 0x1p-1074}; };
    return {p(), p(), p(), p()};
  }, counts);
  check_family(3000, 11, [](Rng& r) -> std::array<Point2, 4> {
    // Every exponent at once, overflowing differences included.
    auto p = [&] { return Point2{r.any_magnitude(-1074, 1020), r.any_magnitude(-1074, 1020)}; };
    return {p(), p(), p(), p()};
  }, counts);
  check_family(3000, 12, [](Rng& r) -> std::array<Point2, 4> {
    // Exponents chosen to make some cross products underflow while lifts stay large.
    auto big = [&] { return r.any_magnitude(300, 420); };
    auto tiny = [&] { return r.any_magnitude(-560, -500); };
    return {Point2{big(), tiny()}, Point2{tiny(), tiny()}, Point2{tiny(), big()},
            Point2{tiny(), tiny()}};
  }, counts);
  CHECK(counts.zero_incircle > 500);
}

// ---- The perturbation ------------------------------------------------------------------------

TEST_CASE("incircle_perturbed equals incircle off the circle and is never zero", "[predicates]") {
  Rng rng(13);
  for (int i = 0; i < 20000; ++i) {
    // Small integer points: plenty of exact ties.
    auto p = [&] { return Point2{double(rng.integer(-3, 3)), double(rng.integer(-3, 3))}; };
    Point2 a = p(), b = p(), c = p(), d = p();
    const int turn = reference_orient2d(a, b, c);
    if (turn == 0 || d == a || d == b || d == c) continue;
    if (turn < 0) std::swap(b, c);
    const int exact = reference_incircle(a, b, c, d);
    const int perturbed = detail::incircle_perturbed(a, b, c, d);
    REQUIRE(perturbed != 0);
    if (exact != 0) REQUIRE(perturbed == exact);
    // Invariant under cyclic rotation of the triangle (CGAL's ordering does not depend on it).
    REQUIRE(detail::incircle_perturbed(b, c, a, d) == perturbed);
    REQUIRE(detail::incircle_perturbed(c, a, b, d) == perturbed);
  }
}

TEST_CASE("perturbation picks one diagonal of every cocircular quadrilateral", "[predicates]") {
  // For p0..p3 cocircular in CCW order, the perturbed lifted points are in convex position, so
  // exactly one diagonal is Delaunay: triangles (p0,p1,p2) and (p2,p3,p0) both exclude the
  // fourth point, or triangles (p1,p2,p3) and (p3,p0,p1) both do.
  long quadrilaterals = 0;
  for (long r2 : {25L, 65L, 325L, 1105L}) {
    const auto circle = integer_circle(r2);
    const int n = int(circle.size());
    for (int i = 0; i < n; ++i)
      for (int j = i + 1; j < n; ++j)
        for (int k = j + 1; k < n; ++k)
          for (int l = k + 1; l < n; ++l) {
            const Point2 &p0 = circle[i], &p1 = circle[j], &p2 = circle[k], &p3 = circle[l];
            const int first = detail::incircle_perturbed(p0, p1, p2, p3);
            REQUIRE(detail::incircle_perturbed(p2, p3, p0, p1) == first);
            REQUIRE(detail::incircle_perturbed(p1, p2, p3, p0) == -first);
            REQUIRE(detail::incircle_perturbed(p3, p0, p1, p2) == -first);
            ++quadrilaterals;
          }
  }
  CHECK(quadrilaterals > 1000);
}

// ---- CGAL agreement ----------------------------------------------------------------------------

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Delaunay = CGAL::Delaunay_triangulation_2<Kernel>;

Kernel::Point_2 to_cgal(const Point2& p) { return {p.x, p.y}; }

using TriangleKey = std::array<int, 3>;

/// Rotates a CCW triangle so its smallest index comes first.
TriangleKey canonical(int a, int b, int c) {
  if (b < a && b < c) return {b, c, a};
  if (c < a && c < b) return {c, a, b};
  return {a, b, c};
}

std::set<TriangleKey> cgal_triangles(const std::vector<Point2>& points) {
  Delaunay dt;
  std::vector<Delaunay::Vertex_handle> handles;
  for (const auto& p : points) handles.push_back(dt.insert(to_cgal(p)));
  std::set<TriangleKey> triangles;
  for (auto face = dt.finite_faces_begin(); face != dt.finite_faces_end(); ++face) {
    int index[3];
    for (int k = 0; k < 3; ++k)
      index[k] = int(std::find(handles.begin(), handles.end(), face->vertex(k)) - handles.begin());
    triangles.insert(canonical(index[0], index[1], index[2]));
  }
  return triangles;
}

/// The Delaunay triangulation of the perturbed set by brute force: a CCW triangle belongs to it
/// iff every other site is outside its perturbed circle.
std::set<TriangleKey> brute_force_triangles(const std::vector<Point2>& points) {
  const int n = int(points.size());
  std::set<TriangleKey> triangles;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) {
        if (i == j || j == k || i == k) continue;
        if (detail::orient2d(points[i], points[j], points[k]) <= 0) continue;
        bool empty = true;
        for (int l = 0; l < n && empty; ++l)
          if (l != i && l != j && l != k)
            empty = detail::incircle_perturbed(points[i], points[j], points[k], points[l]) < 0;
        if (empty) triangles.insert(canonical(i, j, k));
      }
  return triangles;
}

}  // namespace

TEST_CASE("side_of_oriented_circle agrees with CGAL's, ties included", "[predicates][cgal]") {
  Delaunay dt;  // Only its predicate is used; it needs no points.
  Rng rng(14);
  long ties = 0, checked = 0;
  for (int i = 0; i < 30000; ++i) {
    auto p = [&] { return Point2{double(rng.integer(-4, 4)), double(rng.integer(-4, 4))}; };
    Point2 a = p(), b = p(), c = p(), d = p();
    if (a == b || a == c || a == d || b == c || b == d || c == d) continue;
    const int turn = detail::orient2d(a, b, c);
    if (turn == 0) continue;
    if (turn < 0) std::swap(b, c);
    const int expected =
        int(dt.side_of_oriented_circle(to_cgal(a), to_cgal(b), to_cgal(c), to_cgal(d), true));
    REQUIRE(detail::incircle_perturbed(a, b, c, d) == expected);
    ties += detail::incircle(a, b, c, d) == 0;
    ++checked;
  }
  CHECK(ties > 300);
  CHECK(checked > 10000);
}

TEST_CASE("brute-force perturbed Delaunay equals CGAL's triangulation", "[predicates][cgal]") {
  std::vector<std::vector<Point2>> sets;
  // Integer grids: every unit square is a cocircular tie.
  for (int w : {2, 3, 4})
    for (int h : {2, 3, 4}) {
      std::vector<Point2> grid;
      for (int x = 0; x < w; ++x)
        for (int y = 0; y < h; ++y) grid.push_back({double(x), double(y)});
      sets.push_back(grid);
    }
  // Points on integer circles, with and without the centre, shuffled.
  Rng rng(15);
  for (long r2 : {25L, 50L, 65L, 325L}) {
    auto circle = integer_circle(r2);
    std::shuffle(circle.begin(), circle.end(), rng.engine);
    sets.push_back(circle);
    circle.push_back({0, 0});
    sets.push_back(circle);
  }
  // Two concentric cocircular families and a grid mixed with a circle.
  {
    auto set = integer_circle(25);
    for (const auto& p : integer_circle(100)) set.push_back(p);
    sets.push_back(set);
    auto mixed = integer_circle(25);
    for (int x = -1; x <= 1; ++x)
      for (int y = -1; y <= 1; ++y) mixed.push_back({double(x), double(y)});
    sets.push_back(mixed);
  }
  for (const auto& set : sets) {
    INFO("set of " << set.size() << " points starting at " << set[0].x << "," << set[0].y);
    REQUIRE(brute_force_triangles(set) == cgal_triangles(set));
  }
}
