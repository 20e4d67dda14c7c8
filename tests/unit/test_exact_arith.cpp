// The building blocks in predicates/exact_arith.hpp, each checked on its own against GMP:
// error-free transformations, expansions, the filters (never wrong when they decide), the
// exactness certificate, the expansion evaluation, and the start-up self-test.
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <utility>

#include <catch2/catch.hpp>
#include <gmpxx.h>

#include "predicates/apex_filter.hpp"
#include "predicates/exact_arith.hpp"
#include "predicates/predicates.hpp"

namespace exact = expanse::detail::exact;

namespace {

std::mt19937_64& rng() {
  static std::mt19937_64 engine(20240611);
  return engine;
}

int integer(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng()); }
double uniform(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng()); }

/// A double with random mantissa, sign and an exponent in [lo, hi].
double random_double(int lo, int hi) {
  const double mantissa = uniform(1.0, 2.0) * (integer(0, 1) ? 1.0 : -1.0);
  return std::ldexp(mantissa, integer(lo, hi));
}

double nudged(double v) {
  const int steps = integer(-2, 2);
  for (int i = 0; i < std::abs(steps); ++i) v = std::nextafter(v, steps > 0 ? INFINITY : -INFINITY);
  return v;
}

template <int N>
mpq_class value_of(const exact::Expansion<N>& e) {
  mpq_class total = 0;
  for (int i = 0; i < e.size; ++i) total += mpq_class(e.term[i]);
  return total;
}

/// The invariant every expansion must keep: no zeros, increasing magnitude, and each term
/// smaller than the lowest set bit of the next (non-overlapping).
template <int N>
bool well_formed(const exact::Expansion<N>& e) {
  for (int i = 0; i < e.size; ++i) {
    if (e.term[i] == 0.0 || !std::isfinite(e.term[i])) return false;
    if (i + 1 < e.size) {
      // Lowest set bit of the larger term: its ulp times the trailing zero count of its mantissa.
      const double larger = std::fabs(e.term[i + 1]);
      int exponent;
      const double mantissa = std::frexp(larger, &exponent);
      auto bits = static_cast<std::uint64_t>(std::ldexp(mantissa, 53));
      int trailing = 0;
      while ((bits & 1) == 0) bits >>= 1, ++trailing;
      const double lowest_bit = std::ldexp(1.0, exponent - 53 + trailing);
      if (!(std::fabs(e.term[i]) < lowest_bit)) return false;
    }
  }
  return true;
}

int sign_of(const mpq_class& q) { return sgn(q); }

int reference_orient2d(double ax, double ay, double bx, double by, double cx, double cy) {
  const mpq_class acx = mpq_class(ax) - cx, acy = mpq_class(ay) - cy;
  const mpq_class bcx = mpq_class(bx) - cx, bcy = mpq_class(by) - cy;
  return sign_of(acx * bcy - acy * bcx);
}

int reference_incircle(const double* p) {  // ax ay bx by cx cy dx dy
  const mpq_class adx = mpq_class(p[0]) - p[6], ady = mpq_class(p[1]) - p[7];
  const mpq_class bdx = mpq_class(p[2]) - p[6], bdy = mpq_class(p[3]) - p[7];
  const mpq_class cdx = mpq_class(p[4]) - p[6], cdy = mpq_class(p[5]) - p[7];
  return sign_of((adx * adx + ady * ady) * (bdx * cdy - cdx * bdy) +
                 (bdx * bdx + bdy * bdy) * (cdx * ady - adx * cdy) +
                 (cdx * cdx + cdy * cdy) * (adx * bdy - bdx * ady));
}

/// Four points on a circle of radius r in [r_lo, r_hi] about a centre in [-spread, spread]^2,
/// rounded and nudged by a few ulps: near-cocircular.
void near_cocircular(double* p, double spread, double r_lo, double r_hi) {
  const double cx = uniform(-spread, spread), cy = uniform(-spread, spread), r = uniform(r_lo, r_hi);
  for (int i = 0; i < 4; ++i) {
    const double angle = uniform(0, 6.3);
    p[2 * i] = nudged(cx + r * std::cos(angle));
    p[2 * i + 1] = nudged(cy + r * std::sin(angle));
  }
}

/// Eight coordinates of an adversarial incircle case: family 0 random, 1 near-cocircular,
/// 2 small integers (exact ties), 3 large offset with tiny spread.
void adversarial_incircle(int family, double* p) {
  switch (family) {
    case 0:
      for (int i = 0; i < 8; ++i) p[i] = uniform(-1, 1);
      break;
    case 1:
      near_cocircular(p, 2, 0.1, 3);
      break;
    case 2:
      for (int i = 0; i < 8; ++i) p[i] = integer(-5, 5);
      break;
    default:
      for (int i = 0; i < 8; ++i) p[i] = 1e8 + uniform(-1e-6, 1e-6);
      break;
  }
}

}  // namespace

TEST_CASE("the start-up self-test passes and contraction is off here", "[exact]") {
  REQUIRE(expanse::detail::predicates_self_test());
  // This translation unit must not contract either: a*a - p must round a*a first.
  volatile double a_storage = 1.0 + 0x1p-30, p_storage = 1.0 + 0x1p-29;
  const double a = a_storage, p = p_storage;
  REQUIRE(a * a - p == 0.0);
}

TEST_CASE("error-free transformations are exact", "[exact]") {
  for (int i = 0; i < 20000; ++i) {
    const double a = random_double(-180, 180), b = random_double(-180, 180);
    double error;
    const double sum = exact::two_sum(a, b, error);
    REQUIRE(mpq_class(sum) + error == mpq_class(a) + b);
    REQUIRE(sum == a + b);
    const double diff = exact::two_diff(a, b, error);
    REQUIRE(mpq_class(diff) + error == mpq_class(a) - b);
    const double product = exact::two_product(a, b, error);
    REQUIRE(mpq_class(product) + error == mpq_class(a) * b);
    REQUIRE(product == a * b);
    const double big = std::fabs(a) >= std::fabs(b) ? a : b, small = big == a ? b : a;
    const double fast = exact::fast_two_sum(big, small, error);
    REQUIRE(mpq_class(fast) + error == mpq_class(big) + small);
  }
}

TEST_CASE("expansion arithmetic is exact and stays well formed", "[exact]") {
  for (int i = 0; i < 3000; ++i) {
    const double a = random_double(-60, 60), b = random_double(-60, 60);
    const double c = random_double(-60, 60), d = random_double(-60, 60);
    const auto ab = exact::exact_product(a, b);
    const auto cd = exact::exact_difference(c, d);
    const auto sum = ab + cd;
    REQUIRE(well_formed(sum));
    REQUIRE(value_of(sum) == mpq_class(a) * b + (mpq_class(c) - d));
    const auto product = sum * (cd - ab);
    REQUIRE(well_formed(product));
    REQUIRE(value_of(product) == value_of(sum) * (value_of(cd) - value_of(ab)));
    const auto scaled = exact::scale(product, c);
    REQUIRE(well_formed(scaled));
    REQUIRE(value_of(scaled) == value_of(product) * c);
    REQUIRE(product.sign() == sgn(value_of(product)));
    auto compressed = product;
    exact::compress(compressed);
    REQUIRE(well_formed(compressed));
    REQUIRE(value_of(compressed) == value_of(product));
    REQUIRE(compressed.size <= product.size);
    // Cancellation down to exactly zero.
    REQUIRE((sum - sum).size == 0);
  }
}

TEST_CASE("filters are never wrong when they decide", "[exact]") {
  long decided = 0, total = 0;
  for (int family = 0; family < 4; ++family)
    for (int i = 0; i < 5000; ++i) {
      double p[8];
      adversarial_incircle(family, p);
      const int expected_incircle = reference_incircle(p);
      const int incircle = exact::incircle_filter(p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7]);
      if (incircle != exact::uncertain) REQUIRE(incircle == expected_incircle);
      // Reuse the points as a near-degenerate triangle: c nudged onto the line ab.
      const double t = uniform(-1, 2);
      const double cx = nudged(p[0] + t * (p[2] - p[0])), cy = nudged(p[1] + t * (p[3] - p[1]));
      const int expected_orient = reference_orient2d(p[0], p[1], p[2], p[3], cx, cy);
      const int orient = exact::orient2d_filter(p[0], p[1], p[2], p[3], cx, cy);
      if (orient != exact::uncertain) REQUIRE(orient == expected_orient);
      decided += (incircle != exact::uncertain) + (orient != exact::uncertain);
      total += 2;
    }
  // Random inputs are decided by the filter; the adversarial ones mostly are not.
  CHECK(decided > total / 8);
  // A filter must give up rather than answer from underflowed or overflowed intermediates.
  for (int i = 0; i < 5000; ++i) {
    double p[8];
    for (double& v : p) v = integer(-6, 6) * 0x1p-1074;  // products underflow to zero
    const int incircle = exact::incircle_filter(p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7]);
    if (incircle != exact::uncertain) REQUIRE(incircle == reference_incircle(p));
    const int orient = exact::orient2d_filter(p[0], p[1], p[2], p[3], p[4], p[5]);
    if (orient != exact::uncertain) REQUIRE(orient == reference_orient2d(p[0], p[1], p[2], p[3], p[4], p[5]));
  }
  const double huge = std::numeric_limits<double>::max();
  CHECK(exact::orient2d_filter(huge, 0, -huge, 1, 0, -huge) == exact::uncertain);
  CHECK(exact::incircle_filter(1e200, 0, 0, 1e200, -1e200, 0, 0, 0) == exact::uncertain);
}

TEST_CASE("the apex filters in the edge's frame are never wrong when they decide", "[exact]") {
  // Their precondition: |coordinates| < 1, as the backends' scaled sites.
  long decided = 0, total = 0;
  auto check = [&](const double* p) {  // a, b, c, d
    const exact::ApexEdge edge = exact::apex_edge(p[0], p[1], p[2], p[3]);
    const exact::ApexPoint c = exact::apex_point(edge, p[4], p[5]);
    const exact::ApexPoint d = exact::apex_point(edge, p[6], p[7]);
    const exact::ApexLift c_lift = exact::apex_lift(edge, c);
    const int orient_c = exact::apex_orient_filter(c_lift);
    if (orient_c != exact::uncertain) REQUIRE(orient_c == reference_orient2d(p[0], p[1], p[2], p[3], p[4], p[5]));
    const int orient_d = exact::apex_orient_filter(exact::apex_lift(edge, d));
    if (orient_d != exact::uncertain) REQUIRE(orient_d == reference_orient2d(p[0], p[1], p[2], p[3], p[6], p[7]));
    const int incircle = exact::apex_incircle_filter(c_lift, d);
    if (incircle != exact::uncertain) REQUIRE(incircle == reference_incircle(p));
    // The squared distance to a, which the nearest-neighbour search compares.
    REQUIRE(d.d2 == (p[6] - p[0]) * (p[6] - p[0]) + (p[7] - p[1]) * (p[7] - p[1]));
    decided += (incircle != exact::uncertain) + (orient_c != exact::uncertain);
    total += 2;
  };
  long random_decided = 0;
  for (int family = 0; family < 7; ++family) {
    for (int i = 0; i < 5000; ++i) {
      double p[8];
      switch (family) {
        case 0:  // random
          for (double& v : p) v = uniform(-0.99, 0.99);
          break;
        case 1:  // near-cocircular, inside the unit square
          near_cocircular(p, 0.4, 0.05, 0.5);
          break;
        case 2:  // small integers, scaled: exact ties
          for (double& v : p) v = integer(-5, 5) * 0x1p-3;
          break;
        case 3:  // a tiny cluster away from the origin
          for (double& v : p) v = nudged(0.5 + uniform(-1e-9, 1e-9));
          break;
        case 4: {  // d nudged onto the line ab, c anywhere
          for (int k = 0; k < 6; ++k) p[k] = uniform(-0.9, 0.9);
          const double t = uniform(-0.05, 1.05);
          p[6] = nudged(p[0] + t * (p[2] - p[0]));
          p[7] = nudged(p[1] + t * (p[3] - p[1]));
          std::swap(p[4], p[6]);  // and also as c
          std::swap(p[5], p[7]);
          break;
        }
        case 5:  // products underflow
          for (double& v : p) v = integer(-6, 6) * 0x1p-1074;
          break;
        default:  // the smallest sites the backends send (2^-200), and their neighbours
          for (double& v : p) v = random_double(-205, -195);
          break;
      }
      check(p);
      if (family == 0) random_decided = decided;
    }
  }
  // Random inputs are almost always decided.
  CHECK(random_decided > 5000 * 2 * 99 / 100);
  CHECK(decided < total);  // the adversarial families reach `uncertain`
}

TEST_CASE("the exactness certificate decides integer inputs and is never wrong", "[exact]") {
  long integer_decided = 0, integer_total = 0;
  for (int family = 0; family < 4; ++family)
    for (int i = 0; i < 5000; ++i) {
      double p[8];
      adversarial_incircle(family, p);
      const int incircle = exact::incircle_certified(p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7]);
      if (incircle != exact::uncertain) REQUIRE(incircle == reference_incircle(p));
      const int orient = exact::orient2d_certified(p[0], p[1], p[2], p[3], p[4], p[5]);
      if (orient != exact::uncertain)
        REQUIRE(orient == reference_orient2d(p[0], p[1], p[2], p[3], p[4], p[5]));
      if (family == 2) {
        integer_decided += (incircle != exact::uncertain) + (orient != exact::uncertain);
        integer_total += 2;
      }
    }
  // Small integers, also scaled by powers of two, are always certified: no operation rounds.
  CHECK(integer_decided == integer_total);
  for (int i = 0; i < 5000; ++i) {
    double p[8];
    const double scale = std::ldexp(1.0, integer(-150, 150));
    for (double& v : p) v = integer(-500, 500) * scale;
    const int incircle = exact::incircle_certified(p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7]);
    REQUIRE(incircle == reference_incircle(p));
  }
  // Out of the safe range it declines rather than risk an underflowed remainder.
  CHECK(exact::orient2d_certified(0x1p-600, 0, 0, 0x1p-600, 0, 0) == exact::uncertain);
}

TEST_CASE("incircle from exact differences matches the rationals, and declines inexact differences", "[exact]") {
  // Both forms: multiplied out in expansions (the host) and grown from the exact products (the
  // devices, as shaders/include/predicates.glsl does).
  long decided = 0, total = 0;
  for (int family = 0; family < 4; ++family)
    for (int i = 0; i < 3000; ++i) {
      double p[8];
      adversarial_incircle(family, p);
      const double scale = std::ldexp(1.0, integer(-150, 150));
      for (double& v : p) v *= scale;
      const int sign = exact::incircle_exact_differences(p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7]);
      // The devices' form decides the same cases the same way.
      REQUIRE(exact::incircle_exact_differences_grown(p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7]) == sign);
      ++total;
      if (sign == exact::uncertain) continue;
      ++decided;
      REQUIRE(sign == reference_incircle(p));
    }
  CHECK(decided > 0);
  // Decimal grids: four sites of a square of a grid with step 0.1, nearly (not exactly)
  // cocircular once rounded, all within one binade: always decided, and right.
  long grid_decided = 0;
  for (int i = 0; i < 3000; ++i) {
    const int x = integer(1000, 2000), y = integer(1000, 2000), w = integer(1, 3);
    double p[8] = {0.1 * x, 0.1 * y, 0.1 * (x + w), 0.1 * y, 0.1 * (x + w), 0.1 * (y + w), 0.1 * x, 0.1 * (y + w)};
    const int sign = exact::incircle_exact_differences(p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7]);
    REQUIRE(exact::incircle_exact_differences_grown(p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7]) == sign);
    grid_decided += sign != exact::uncertain;
    if (sign != exact::uncertain) REQUIRE(sign == reference_incircle(p));
  }
  CHECK(grid_decided == 3000);
  // A difference that rounds: declined, not guessed.
  CHECK(exact::incircle_exact_differences(1.0, 0.0, 0.0, 1.0, -1.0, 0.0, 0x1p-60, 0.0) == exact::uncertain);
}

TEST_CASE("expansion evaluation matches the rationals in the safe range", "[exact]") {
  for (int family = 0; family < 4; ++family)
    for (int i = 0; i < 2000; ++i) {
      double p[8];
      adversarial_incircle(family, p);
      // Spread the magnitudes over the whole safe range, with exact power-of-two scaling.
      const double scale = std::ldexp(1.0, integer(-150, 150));
      for (double& v : p) v *= scale;
      REQUIRE(exact::incircle_expansion(p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7]) ==
              reference_incircle(p));
      REQUIRE(exact::orient2d_expansion(p[0], p[1], p[2], p[3], p[4], p[5]) ==
              reference_orient2d(p[0], p[1], p[2], p[3], p[4], p[5]));
    }
  for (int i = 0; i < 2000; ++i) {
    double p[8];
    for (double& v : p) v = random_double(-200, 199);  // every exponent the range allows
    REQUIRE(exact::incircle_expansion(p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7]) ==
            reference_incircle(p));
  }
}
