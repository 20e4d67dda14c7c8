#pragma once
// Basic value types shared by every part of Expanse.
#include <array>
#include <cstdint>

namespace expanse {

/// An input point. Coordinates are finite doubles; Expanse never changes them.
struct Point2 {
  double x = 0.0;
  double y = 0.0;
  friend bool operator==(const Point2&, const Point2&) = default;
};

/// Three indices into the caller's point array, counter-clockwise:
///
///        v2
///       /  \        neighbors[t][k] is the triangle across the edge opposite v_k,
///      /    \       or no_neighbor on the convex hull (scipy's convention).
///    v0 ---- v1
using Triangle = std::array<std::int32_t, 3>;

/// Sentinel for "no triangle across this edge" (a hull edge).
inline constexpr std::int32_t no_neighbor = -1;

}  // namespace expanse
