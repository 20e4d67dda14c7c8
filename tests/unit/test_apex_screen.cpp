// The single-precision screen of the apex searches (predicates/apex_screen.hpp) against exact
// rational arithmetic: every sign it claims must be the exact sign, on random and adversarial
// inputs (nearly collinear, nearly cocircular, nearly equidistant, tiny and wide spreads,
// coordinates at the edge of the unit box, differences too small for floats), and it must decide
// the generic candidates it exists for.
#include <catch2/catch.hpp>
#include <gmpxx.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <string>

#include "expanse/types.hpp"
#include "predicates/apex_screen.hpp"

using expanse::Point2;
namespace ex = expanse::detail::exact;

namespace {

int exact_orient(const Point2& a, const Point2& b, const Point2& p) {
  const mpq_class ax(a.x), ay(a.y), bx(b.x), by(b.y), px(p.x), py(p.y);
  return sgn((bx - ax) * (py - ay) - (by - ay) * (px - ax));
}

/// The lifted determinant of (a, b, c, p) about p: positive when p is inside the circle of a
/// counter-clockwise (a, b, c).
int exact_incircle(const Point2& a, const Point2& b, const Point2& c, const Point2& p) {
  const Point2* q[3] = {&a, &b, &c};
  mpq_class x[3], y[3], l[3];
  for (int i = 0; i < 3; ++i) {
    x[i] = mpq_class(q[i]->x) - mpq_class(p.x);
    y[i] = mpq_class(q[i]->y) - mpq_class(p.y);
    l[i] = x[i] * x[i] + y[i] * y[i];
  }
  const mpq_class det = x[0] * (y[1] * l[2] - l[1] * y[2]) - y[0] * (x[1] * l[2] - l[1] * x[2]) +
                        l[0] * (x[1] * y[2] - y[1] * x[2]);
  return sgn(det);
}

/// Sign of |p - s|^2 - |c - s|^2.
int exact_distance_order(const Point2& s, const Point2& p, const Point2& c) {
  const mpq_class px = mpq_class(p.x) - s.x, py = mpq_class(p.y) - s.y;
  const mpq_class cx = mpq_class(c.x) - s.x, cy = mpq_class(c.y) - s.y;
  return sgn(px * px + py * py - (cx * cx + cy * cy));
}

/// The frame a search's walk builds (star_scan.cuh): a's float copy, B and C from doubles.
ex::ScreenFrame frame_of(const Point2& a, const Point2& b, const Point2& c) {
  ex::ScreenFrame f;
  f.ax = ex::nearest_float(a.x);
  f.ay = ex::nearest_float(a.y);
  f.bx = ex::screen_leaf(b.x, a.x);
  f.by = ex::screen_leaf(b.y, a.y);
  f.cx = ex::screen_leaf(c.x, a.x);
  f.cy = ex::screen_leaf(c.y, a.y);
  return f;
}

/// How often the screen decided each question, over a run of samples.
struct Decided {
  long orient = 0, incircle = 0, distance = 0, samples = 0, left_samples = 0;
};

/// Every claim of the screen on (a, b, c, p) checked against the exact signs.
void check_sample(const Point2& a, const Point2& b, const Point2& c, const Point2& p, Decided& decided,
                  const std::string& family) {
  INFO(family << ": a (" << a.x << ", " << a.y << ") b (" << b.x << ", " << b.y << ") c (" << c.x << ", " << c.y
              << ") p (" << p.x << ", " << p.y << ")");
  const float px = ex::nearest_float(p.x), py = ex::nearest_float(p.y);
  const int o = exact_orient(a, b, p);
  ++decided.samples;

  // Apex search with no best yet: better iff certainly left, rejected iff certainly right.
  const ex::ScreenFrame apex = frame_of(a, b, c);
  const ex::ScreenVerdict first = ex::apex_screen(apex, px, py, false, false);
  if (first.better) REQUIRE(o > 0);
  if (first.reject) REQUIRE(o < 0);
  REQUIRE(first.left == first.better);
  decided.orient += first.better || first.reject;

  // Against a best c: better only left and inside (a, b, c)'s circle; rejected only right, or
  // left and outside. (The walk's c is left of a->b; the claims hold for any c.)
  const ex::ScreenVerdict against = ex::apex_screen(apex, px, py, false, true);
  REQUIRE(!(against.better && against.reject));
  if (against.left) REQUIRE(o > 0);
  if (o > 0) {
    const int in = exact_incircle(a, b, c, p);
    if (against.better) REQUIRE(in > 0);
    if (against.reject) REQUIRE(in < 0);
    ++decided.left_samples;
    decided.incircle += against.better || against.reject;
  } else {
    REQUIRE(!against.better);
  }

  // Nearest-neighbour search from s = a, best c: the frame has no B.
  ex::ScreenFrame nearest = apex;
  nearest.bx = nearest.by = 0.0f;
  const ex::ScreenVerdict near = ex::apex_screen(nearest, px, py, true, true);
  const int order = exact_distance_order(a, p, c);
  if (near.better) REQUIRE(order < 0);
  if (near.reject) REQUIRE(order > 0);
  REQUIRE(!near.left);
  decided.distance += near.better || near.reject;
  const ex::ScreenVerdict none = ex::apex_screen(nearest, px, py, true, false);
  REQUIRE(none.better);
  REQUIRE(!none.reject);
}

struct Sampler {
  std::mt19937_64 random{2026'11'26};
  double unit() { return std::uniform_real_distribution<double>(-1.0, 1.0)(random); }
  int between(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(random); }
  /// A coordinate near `centre`, `scale` away at most, kept inside the open unit box (mirrored
  /// about the centre where it would leave it: clamped, many would share a coordinate).
  double near(double centre, double scale) {
    const double v = centre + scale * unit();
    const double in = std::fabs(v) < 1.0 ? v : 2.0 * centre - v;
    return std::fmax(-0x1.fffffffffffffp-1, std::fmin(0x1.fffffffffffffp-1, in));
  }
  Point2 near(const Point2& centre, double scale) { return {near(centre.x, scale), near(centre.y, scale)}; }
  /// A centre anywhere in the box, or at its rim, or at the origin.
  Point2 centre() {
    switch (between(0, 3)) {
      case 0: return {unit(), unit()};
      case 1: return {0x1.fffffp-1 * (unit() < 0 ? -1 : 1), unit()};
      case 2: return {0.0, 0.0};
      default: return {std::ldexp(unit(), -between(1, 40)), std::ldexp(unit(), -between(1, 40))};
    }
  }
};

Point2 rounded_to_float(const Point2& p) { return {static_cast<float>(p.x), static_cast<float>(p.y)}; }

}  // namespace

TEST_CASE("apex screen: generic candidates are decided, and every sign it gives is exact", "[predicates][screen]") {
  Sampler s;
  Decided decided;
  for (int k = 0; k < 40000; ++k) {
    // Sites a few spacings apart, at spacings from 1/4 down to 2^-12 (16M sites in the box).
    const double scale = std::ldexp(1.0, -s.between(2, 12));
    const Point2 centre = s.centre();
    check_sample(s.near(centre, scale), s.near(centre, scale), s.near(centre, scale), s.near(centre, scale), decided,
                 "generic");
  }
  INFO("orient " << decided.orient << ", incircle " << decided.incircle << " of " << decided.left_samples
                 << ", distance " << decided.distance << " of " << decided.samples);
  // A screen that decides nothing would pass every check above; this one must earn its place.
  CHECK(decided.orient >= 0.99 * decided.samples);
  CHECK(decided.incircle >= 0.99 * decided.left_samples);
  CHECK(decided.distance >= 0.99 * decided.samples);
}

TEST_CASE("apex screen: adversarial candidates get the exact sign or none", "[predicates][screen]") {
  Sampler s;
  Decided decided;
  for (int k = 0; k < 30000; ++k) {
    const double scale = std::ldexp(1.0, -s.between(1, 60));
    const Point2 centre = s.centre();
    const Point2 a = s.near(centre, scale), b = s.near(centre, scale), c = s.near(centre, scale);
    const double tiny = std::ldexp(scale, -s.between(10, 70));
    // Nearly on the line a-b.
    const double t = 3.0 * s.unit();
    const Point2 on_line{a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)};
    check_sample(a, b, c, s.near(on_line, tiny), decided, "near collinear");
    check_sample(a, b, c, on_line, decided, "collinear in doubles");
    // Nearly on the circle through a, b, c (its centre and radius in long double).
    const long double d = 2.0L * ((long double)a.x * (b.y - c.y) + (long double)b.x * (c.y - a.y) +
                                  (long double)c.x * (a.y - b.y));
    if (d != 0.0L) {
      const long double a2 = (long double)a.x * a.x + (long double)a.y * a.y,
                        b2 = (long double)b.x * b.x + (long double)b.y * b.y,
                        c2 = (long double)c.x * c.x + (long double)c.y * c.y;
      const long double ux = (a2 * (b.y - c.y) + b2 * (c.y - a.y) + c2 * (a.y - b.y)) / d;
      const long double uy = (a2 * (c.x - b.x) + b2 * (a.x - c.x) + c2 * (b.x - a.x)) / d;
      const long double r = std::hypot((long double)a.x - ux, (long double)a.y - uy);
      const long double angle = 3.14159265358979L * s.unit();
      const Point2 on_circle{static_cast<double>(ux + r * std::cos(angle)), static_cast<double>(uy + r * std::sin(angle))};
      if (std::fabs(on_circle.x) < 1.0 && std::fabs(on_circle.y) < 1.0) {
        check_sample(a, b, c, on_circle, decided, "near cocircular");
        check_sample(a, b, c, s.near(on_circle, tiny), decided, "near cocircular, nudged");
      }
    }
    // Nearly as far from a as c is: c turned about a.
    const double turn = s.unit();
    const Point2 turned{a.x + std::cos(turn) * (c.x - a.x) - std::sin(turn) * (c.y - a.y),
                        a.y + std::sin(turn) * (c.x - a.x) + std::cos(turn) * (c.y - a.y)};
    if (std::fabs(turned.x) < 1.0 && std::fabs(turned.y) < 1.0) check_sample(a, b, c, turned, decided, "equidistant");
    // Sites that are floats already (the screen's copies are exact, though it does not know).
    check_sample(rounded_to_float(a), rounded_to_float(b), rounded_to_float(c), rounded_to_float(s.near(a, scale)),
                 decided, "float sites");
    // One leaf far longer than the others: a distant b, a close p.
    check_sample(a, s.near(centre, 0.5), c, s.near(a, tiny), decided, "wide spread");
    // Shared coordinates and repeated points: exact zeros.
    check_sample(a, b, c, Point2{a.x, b.y}, decided, "shared coordinates");
    check_sample(a, b, c, c, decided, "p = c");
    check_sample(a, b, c, a, decided, "p = a");
  }
}

TEST_CASE("apex screen: differences beyond float range are left to the double filters", "[predicates][screen]") {
  // Sites 2^-60 apart: the incircle's terms (degree 4) fall below 2^-240, under floats' range,
  // and the distances' below 2^-120; whatever the screen computes there, it claims no sign
  // unless it is exact, and it claims none from underflowed values.
  Sampler s;
  Decided decided;
  for (int k = 0; k < 5000; ++k) {
    const double scale = std::ldexp(1.0, -s.between(35, 70));
    const Point2 centre = s.centre();
    check_sample(s.near(centre, scale), s.near(centre, scale), s.near(centre, scale), s.near(centre, scale), decided,
                 "tiny spread");
  }
  CHECK(decided.incircle == 0);
}
