#pragma once
// The floating-point filters of an apex search, in the frame of its edge. A search for the apex
// of a->b tests many candidates p against one edge and one best candidate c at a time; shifted
// to a (B = b - a, C = c - a, P = p - a), its two predicates are
//   orient2d(a, b, p)    = Bx Py - By Px
//   incircle(a, b, c, p) = (Px Vx + Py Vy) - |P|^2 K,  K = Bx Cy - By Cx,
//                          Vx = |B|^2 Cy - By |C|^2,   Vy = Bx |C|^2 - |B|^2 Cx
// (the lifted 3x3 determinant expanded along p's row). K and V are c's "lift" (K is orient2d's
// value for c). A candidate costs about half the arithmetic of orient2d_filter and
// incircle_filter together, the best's lift included: the star kernels form it again for each
// candidate, since keeping its six doubles live in the loop cost more than it saved (lavapipe
// and the H100 both). The decisions are the same up to `uncertain`: a sign returned is the
// exact sign, and what the filter cannot decide goes to the same exact procedures as before
// (with the original points).
//
// Error bounds. Every leaf (a coordinate difference) is rounded once. Expanded into monomials of
// the leaves, the determinant's every monomial carries at most 11 roundings: its four leaves'
// (a squared leaf's twice) and those of the operations that combine it (Px By Cx^2: Cx^2, |C|^2,
// By |C|^2, Vx, Px Vx and the two sums), the last of them the result's own, which keeps the
// sign. So |computed - exact| is bounded as for a monomial of Shewchuk's incircle, which
// carries as many (adx^2 bdx cdy: its four leaves' and seven operations'), by his bound (10 eps,
// with its second-order terms and the filters' widening) times the permanent, the same
// expression over magnitudes (|Px| Vx_perm + |Py| Vy_perm + |P|^2 K_perm), itself rounded no
// deeper than his. orient2d's form is Shewchuk's exactly.
// Underflow is handled as exact_arith.hpp's filters do (widened bound, `trusted` where the
// absolute losses provably fit in the widening); the loss count assumes |coordinates| < 1,
// which the backends' scaled sites satisfy (SiteSet), so differences are below 2.
#include "predicates/exact_arith.hpp"

namespace expanse::detail::exact {

/// The apex filters' bound factors: orient2d_filter_bound and incircle_filter_bound rounded up
/// (by under 10^-6 of themselves) to doubles whose low 32 bits are zero. A wider bound keeps the
/// filter sound and leaves it a sliver more to the exact path; such a factor is an immediate
/// operand of the H100's double multiply, where the exact factors took two uniform-register
/// moves each in every candidate of the CUDA scan (4 of its 81 instructions).
inline constexpr double apex_orient_bound = 0x1.80001p-52;
inline constexpr double apex_incircle_bound = 0x1.40001p-50;
static_assert(apex_orient_bound >= orient2d_filter_bound && apex_orient_bound <= orient2d_filter_bound * (1 + 1e-6));
static_assert(apex_incircle_bound >= incircle_filter_bound && apex_incircle_bound <= incircle_filter_bound * (1 + 1e-6));

/// The edge a->b of an apex search: a, and B = b - a with |B|^2.
struct ApexEdge {
  double ax, ay, bx, by, b2;
};

/// A candidate's lift against its edge, and the magnitudes its error bound needs.
struct ApexLift {
  double k = 0.0, vx = 0.0, vy = 0.0;
  double k_perm = 0.0, vx_perm = 0.0, vy_perm = 0.0;
};

/// One candidate in the edge's frame: P = p - a and |P|^2 (the squared distance to a).
struct ApexPoint {
  double x, y, d2;
};

EXPANSE_HD inline ApexEdge apex_edge(double ax, double ay, double bx, double by) {
  const double ex = sub(bx, ax), ey = sub(by, ay);
  return {ax, ay, ex, ey, add(mul(ex, ex), mul(ey, ey))};
}

EXPANSE_HD inline ApexPoint apex_point(const ApexEdge& e, double px, double py) {
  const double x = sub(px, e.ax), y = sub(py, e.ay);
  return {x, y, add(mul(x, x), mul(y, y))};
}

/// p's lift: what later candidates are tested against once p is the best.
EXPANSE_HD inline ApexLift apex_lift(const ApexEdge& e, const ApexPoint& p) {
  const double k_left = mul(e.bx, p.y), k_right = mul(e.by, p.x);
  const double vx_left = mul(e.b2, p.y), vx_right = mul(e.by, p.d2);
  const double vy_left = mul(e.bx, p.d2), vy_right = mul(e.b2, p.x);
  return {sub(k_left, k_right),
          sub(vx_left, vx_right),
          sub(vy_left, vy_right),
          add(magnitude(k_left), magnitude(k_right)),
          add(magnitude(vx_left), magnitude(vx_right)),
          add(magnitude(vy_left), magnitude(vy_right))};
}

/// A filter's verdict as two flags: the value is certainly positive, certainly negative, or
/// (neither) undecided. Kernels that only branch on a sign test these directly rather than
/// build the -1/1/`uncertain` code and compare it again (the CUDA candidate loop: fewer
/// integer instructions a candidate).
struct FilterSigns {
  bool positive, negative;
};

EXPANSE_HD inline int sign_code(FilterSigns s) { return s.positive ? 1 : s.negative ? -1 : uncertain; }

/// orient2d(a, b, p) from p's lift (its K); as orient2d_filter.
EXPANSE_HD inline FilterSigns apex_orient_signs(const ApexLift& p) {
  const bool trusted = p.k_perm >= 0x1p-974;
  const double bound = mul(apex_orient_bound, p.k_perm);
  return {trusted && p.k > bound, trusted && -p.k > bound};
}

/// Sign of orient2d(a, b, p) from p's lift (its K), or `uncertain`; as orient2d_filter.
EXPANSE_HD inline int apex_orient_filter(const ApexLift& p) { return sign_code(apex_orient_signs(p)); }

/// incircle(a, b, c, p) from c's lift as apex_incircle_filter evaluates it: exact where every
/// value it forms is an integer multiple of one unit below 2^53 units (small integer lattices:
/// exact_lattice_arithmetic in cuda_backend/star_grid.hpp).
EXPANSE_HD inline double apex_incircle_value(const ApexLift& c, const ApexPoint& p) {
  return sub(add(mul(p.x, c.vx), mul(p.y, c.vy)), mul(p.d2, c.k));
}

/// incircle(a, b, c, p) for the candidate c whose lift is `c`.
EXPANSE_HD inline FilterSigns apex_incircle_signs(const ApexLift& c, const ApexPoint& p) {
  const double ax = magnitude(p.x), ay = magnitude(p.y);
  const double det = apex_incircle_value(c, p);
  const double permanent = add(add(mul(ax, c.vx_perm), mul(ay, c.vy_perm)), mul(p.d2, c.k_perm));
  // Underflow losses (differences below 2): |C|^2's and |B|^2's through V and then |Px|, |Py|
  // (2^-1071 each), K's products through |P|^2, |P|^2's through K, the last three products: at
  // most (|Px| + |Py| + |P|^2 + K_perm + 1) 2^-969, and with |coordinates| < 1 (|Px|, |Py| <= 2,
  // |P|^2 <= 8, K_perm <= 8, each bound representable, so no rounding passes it) under
  // 21 * 2^-969. A permanent of 2^-964 covers them: a constant, where the sum had cost the CUDA
  // candidate loop five of its 46 floating-point operations.
  const bool trusted = permanent >= 0x1p-964;
  const double bound = mul(apex_incircle_bound, permanent);
  return {trusted && det > bound, trusted && -det > bound};
}

/// Sign of incircle(a, b, c, p) for the candidate c whose lift is `c`, or `uncertain`.
EXPANSE_HD inline int apex_incircle_filter(const ApexLift& c, const ApexPoint& p) {
  return sign_code(apex_incircle_signs(c, p));
}

}  // namespace expanse::detail::exact
