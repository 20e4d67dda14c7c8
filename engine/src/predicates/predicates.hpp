#pragma once
// Exact geometric predicates on the host: a floating-point filter with a proven error bound,
// an exact fallback in expansion arithmetic, and GMP for inputs whose degree-4 terms would
// under- or overflow doubles. Correct for every finite input.
#include "expanse/types.hpp"

namespace expanse::detail {

/// +1 if c lies strictly left of a->b (a, b, c counter-clockwise), -1 if right, 0 if collinear.
int orient2d(const Point2& a, const Point2& b, const Point2& c);

/// For counter-clockwise (a, b, c): +1 if d lies strictly inside their circle, -1 if strictly
/// outside, 0 if on it.
int incircle(const Point2& a, const Point2& b, const Point2& c, const Point2& d);

/// incircle() with CGAL's symbolic perturbation (Delaunay_triangulation_2::
/// side_of_oriented_circle with perturb = true): never 0 for CCW (a, b, c) and d distinct from
/// them. +1 means d is inside the perturbed circle.
int incircle_perturbed(const Point2& a, const Point2& b, const Point2& c, const Point2& d);

}  // namespace expanse::detail
