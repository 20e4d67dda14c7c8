#pragma once
// A single-precision screen in front of the apex filters (apex_filter.hpp): the same two
// predicates of an apex search, and the nearest-neighbour search's distance comparison, in float
// arithmetic on a float copy of the sites. A sign it returns is the exact sign; what it cannot
// decide goes to the double filters, and from there to the exact procedures, as before. So it
// changes no decision, only what a decision costs: on a GPU whose FP32 pipes issue twice as fast
// as its FP64 pipes (the H100), most candidates of a search are settled in floats, and a warp takes
// the double path only where one of its lanes meets a candidate the screen leaves open. Counted on
// the CPU before it was built (session 19, 10^6 to 4 * 10^6 uniform, kuzmin and gaussian sites):
// 65% of the apex searches' candidates are rejections, and a float screen decides 99.3-99.9% of them.
//
// The frame. Shifted to a, the predicates are polynomials in the leaves P = p - a, B = b - a and
// C = c - a (apex_filter.hpp's forms):
//   orient2d(a, b, p)    = K(P) = Bx Py - By Px
//   incircle(a, b, c, p) = I(P) = (Px Vx + Py Vy) - |P|^2 K,  K = Bx Cy - By Cx,
//                          Vx = |B|^2 Cy - By |C|^2,   Vy = Bx |C|^2 - |B|^2 Cx
//   nearest neighbour (a = s): |P|^2 against |C|^2, c the best so far.
// B and C change once an edge or once a better candidate; they are formed in double and rounded
// to float (screen_leaf), so each carries a relative error only: (1 + 2^-53)(1 + u) - 1 <= 1.0001 u
// (u = 2^-24), about one rounding. P changes with every candidate, so it is formed in floats from
// the float copies p~ and a~ of the sites: fl(p~ - a~). The sites' coordinates are below 1 in
// magnitude (SiteSet scales them so), so each rounding to float moves a coordinate by at most
// 2^-25, and p~ - a~ = P' = P + d with |dx|, |dy| <= delta = 2^-24: the screen evaluates the
// predicates at a perturbed candidate P' (rounded once more by the subtraction, relatively).
//
// The bound is the sum of three parts, each proved below for every value the screen compares.
//  1. Rounding, at P'. Every leaf carries one relative rounding (B, C: 1.0001 u; P': the
//     subtraction's u) and every operation one more; the longest paths from a leaf to a result
//     hold 4 roundings (K), 8 (I, as apex_filter.hpp counts them) and 3 (|P|^2), so the computed
//     value differs from the exact value at P' by at most gamma_n times the permanent (the same
//     expression over magnitudes), gamma_8 < 8.001 u; the permanent computed in floats is at least
//     (1 - gamma_8) times the exact one. The screen uses 8 u (K), 16 u (I) and 16 u (distances):
//     each at least twice what is needed, the slack covering the float rounding of the bound itself
//     (a few operations, a few u) and of the two sums compared in the nearest-neighbour test.
//  2. The input's rounding, from P' back to P (the exact leaves, with exact B and C):
//     K(P') - K(P) = Bx dy - By dx                      <= delta (|Bx| + |By|),
//     I(P') - I(P) = dx Vx + dy Vy - (2 P'.d - |d|^2) K <= delta (|Vx| + |Vy| + 2 |K| (|P'x| + |P'y| + delta)),
//     |P'|^2 - |P|^2                                   <= 2 delta (|P'x| + |P'y| + delta),
//     with |Bx| etc. bounded by the computed magnitudes (within a few u of the exact ones), hence
//     delta' = delta (1 + 2^-6) in the bound.
//  3. Underflow. A float result below 2^-126 may lose up to 2^-126 absolutely (flushed to zero
//     or gradual), a leaf too. Every leaf is below 2 in magnitude, so a loss reaches a result
//     multiplied by at most a partial derivative of the permanent: 12 monomials of degree 4 with
//     leaves below 2 give less than 2^9. Some 40 roundings and leaves, each at most 2^-126 * 2^9,
//     stay below 2^-111; screen_floor = 2^-100 covers them many times over.
// The bound's parts are computed in floats and nothing in them can overflow (leaves below 2).
// A value whose magnitude exceeds its bound has the sign of the exact predicate.
//
// All arithmetic goes through fadd/fsub/fmul: no contraction into fma (exact_arith.hpp's rule).
#include "predicates/exact_arith.hpp"

namespace expanse::detail::exact {

EXPANSE_HD inline float fadd(float a, float b) {
#if defined(__CUDA_ARCH__)
  return __fadd_rn(a, b);
#else
  return a + b;
#endif
}

EXPANSE_HD inline float fsub(float a, float b) {
#if defined(__CUDA_ARCH__)
  return __fsub_rn(a, b);
#else
  return a - b;
#endif
}

EXPANSE_HD inline float fmul(float a, float b) {
#if defined(__CUDA_ARCH__)
  return __fmul_rn(a, b);
#else
  return a * b;
#endif
}

EXPANSE_HD inline float fmagnitude(float a) {
#if defined(__CUDA_ARCH__)
  return fabsf(a);
#else
  return __builtin_fabsf(a);
#endif
}

/// x rounded to the nearest float (how the float copy of the sites is made).
EXPANSE_HD inline float nearest_float(double x) {
#if defined(__CUDA_ARCH__)
  return __double2float_rn(x);
#else
  return static_cast<float>(x);
#endif
}

/// A leaf formed once per edge or per best candidate: p - a in double, then rounded to float.
EXPANSE_HD inline float screen_leaf(double p, double a) { return nearest_float(sub(p, a)); }

/// What one search's screen holds: a's float copy, and B and C as screen_leaf forms them (B is
/// zero in a nearest-neighbour search, C is unused before the search has a best candidate).
struct ScreenFrame {
  float ax = 0.0f, ay = 0.0f;
  float bx = 0.0f, by = 0.0f;
  float cx = 0.0f, cy = 0.0f;
};

inline constexpr float screen_u = 0x1p-24f;
/// delta' of the bound's second part: the sites' float rounding, 2^-25 per coordinate, twice,
/// widened by 2^-6 for the few u between exact and computed magnitudes.
inline constexpr float screen_input = 0x1p-24f * (1.0f + 0x1p-6f);
inline constexpr float screen_delta = 0x1p-24f;
inline constexpr float screen_floor = 0x1p-100f;

/// The screen's verdict on a candidate: certainly better than the best (a nearer site, or a left
/// apex inside the best's circle), certainly not, or neither (the double filters decide). `left`:
/// the candidate is certainly left of the edge (the apex searches' predicate count).
struct ScreenVerdict {
  bool better, reject, left;
};

/// Candidate p (its float copy) against the frame: in the nearest-neighbour search (nearest)
/// against the best's distance, otherwise as an apex of a->b against the best's circle; with no
/// best yet (has_best false) a nearest neighbour is better outright, an apex once it is left of
/// a->b. Straight-line: both searches' values are formed, and the search picks its verdict.
EXPANSE_HD inline ScreenVerdict apex_screen(const ScreenFrame& f, float px, float py, bool nearest, bool has_best) {
  constexpr float u = screen_u;
  const float x = fsub(px, f.ax), y = fsub(py, f.ay);
  const float mx = fmagnitude(x), my = fmagnitude(y);
  const float d2 = fadd(fmul(x, x), fmul(y, y));
  const float reach = fadd(fadd(mx, my), screen_delta);  // |P'x| + |P'y| + delta

  // The best's lift against B (the double filters' apex_lift, in floats).
  const float b2 = fadd(fmul(f.bx, f.bx), fmul(f.by, f.by)), c2 = fadd(fmul(f.cx, f.cx), fmul(f.cy, f.cy));
  const float k_l = fmul(f.bx, f.cy), k_r = fmul(f.by, f.cx);
  const float vx_l = fmul(b2, f.cy), vx_r = fmul(f.by, c2);
  const float vy_l = fmul(f.bx, c2), vy_r = fmul(b2, f.cx);
  const float k = fsub(k_l, k_r), vx = fsub(vx_l, vx_r), vy = fsub(vy_l, vy_r);
  const float k_perm = fadd(fmagnitude(k_l), fmagnitude(k_r));
  const float vx_perm = fadd(fmagnitude(vx_l), fmagnitude(vx_r));
  const float vy_perm = fadd(fmagnitude(vy_l), fmagnitude(vy_r));

  // orient2d(a, b, p).
  const float o_l = fmul(f.bx, y), o_r = fmul(f.by, x);
  const float o = fsub(o_l, o_r);
  const float o_perm = fadd(fmagnitude(o_l), fmagnitude(o_r));
  const float o_bound = fadd(fadd(fmul(8.0f * u, o_perm), fmul(screen_input, fadd(fmagnitude(f.bx), fmagnitude(f.by)))),
                             screen_floor);
  const bool o_pos = o > o_bound, o_neg = -o > o_bound;

  // incircle(a, b, c, p).
  const float ic = fsub(fadd(fmul(x, vx), fmul(y, vy)), fmul(d2, k));
  const float ic_perm = fadd(fadd(fmul(mx, vx_perm), fmul(my, vy_perm)), fmul(d2, k_perm));
  const float ic_input = fmul(screen_input, fadd(fadd(vx_perm, vy_perm), fmul(fadd(k_perm, k_perm), reach)));
  const float ic_bound = fadd(fadd(fmul(16.0f * u, ic_perm), ic_input), screen_floor);
  const bool ic_pos = ic > ic_bound, ic_neg = -ic > ic_bound;

  // |p - s|^2 against |c - s|^2 (a = s).
  const float p_bound = fadd(fadd(fmul(16.0f * u, d2), fmul(2.0f * screen_input, reach)), screen_floor);
  const float c_bound = fadd(fmul(16.0f * u, c2), screen_floor);
  const bool nearer = fadd(fadd(d2, p_bound), c_bound) < c2;
  const bool farther = fsub(d2, p_bound) > fadd(c2, c_bound);

  if (nearest) return {!has_best || nearer, has_best && farther, false};
  return {o_pos && (!has_best || ic_pos), o_neg || (o_pos && has_best && ic_neg), o_pos};
}

}  // namespace expanse::detail::exact
