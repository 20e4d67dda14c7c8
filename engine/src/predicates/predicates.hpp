#pragma once
// Exact geometric predicates on the host: a floating-point filter with a proven error bound,
// an exact fallback in expansion arithmetic, and GMP for inputs whose degree-4 terms would
// under- or overflow doubles. Correct for every finite input.
//
// The filter is inline because the apex search calls these billions of times; everything the
// filter cannot decide goes to one out-of-line function per predicate.
#include "expanse/types.hpp"
#include "predicates/exact_arith.hpp"

namespace expanse::detail {

/// Out-of-line exact evaluation (certificate, then expansions, then rationals).
int orient2d_exact(const Point2& a, const Point2& b, const Point2& c);
int incircle_exact(const Point2& a, const Point2& b, const Point2& c, const Point2& d);

/// +1 if c lies strictly left of a->b (a, b, c counter-clockwise), -1 if right, 0 if collinear.
inline int orient2d(const Point2& a, const Point2& b, const Point2& c) {
  const int sign = exact::orient2d_filter(a.x, a.y, b.x, b.y, c.x, c.y);
  if (sign != exact::uncertain) [[likely]]
    return sign;
  return orient2d_exact(a, b, c);
}

/// For counter-clockwise (a, b, c): +1 if d lies strictly inside their circle, -1 if strictly
/// outside, 0 if on it.
inline int incircle(const Point2& a, const Point2& b, const Point2& c, const Point2& d) {
  const int sign = exact::incircle_filter(a.x, a.y, b.x, b.y, c.x, c.y, d.x, d.y);
  if (sign != exact::uncertain) [[likely]]
    return sign;
  return incircle_exact(a, b, c, d);
}

/// incircle() with CGAL's symbolic perturbation (Delaunay_triangulation_2::
/// side_of_oriented_circle with perturb = true): never 0 for CCW (a, b, c) and d distinct from
/// them. +1 means d is inside the perturbed circle.
int incircle_perturbed(const Point2& a, const Point2& b, const Point2& c, const Point2& d);

/// The sign CGAL's perturbation gives to an exactly cocircular d (incircle == 0); exposed so
/// that device code which decided incircle == 0 itself can share the tie-break.
int perturbed_tie_break(const Point2& a, const Point2& b, const Point2& c, const Point2& d);

/// Start-up check that this build's arithmetic keeps the error-free transformations exact
/// (no fma contraction, round-to-nearest, gradual underflow). False means the predicates
/// cannot be trusted.
bool predicates_self_test();

}  // namespace expanse::detail
