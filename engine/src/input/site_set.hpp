#pragma once
// Validated, normalised, duplicate-free input: what every backend and the seam stage work on.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "expanse/types.hpp"
#include "input/parallel.hpp"
#include "predicates/exact_lattice.hpp"

namespace expanse::detail {

struct Box {
  double min_x = 0, min_y = 0, max_x = 0, max_y = 0;
};

/// What a pass over the raw input learns: that every coordinate is finite, the power of two to
/// scale by, and the box of the scaled points.
struct InputScan {
  /// Power of two the input is scaled by, so that the largest |coordinate| lies in [0.5, 1)
  /// (less where that would push a nonzero coordinate below the smallest normal double).
  int scale_exponent = 0;
  Box bounds;  ///< of the scaled points
  double factor = 1.0;  ///< 2^scale_exponent, or 0 where that overflows (ldexp then)
  /// Every input coordinate an integer: a lattice, whose cocircular cells make the devices
  /// settle many candidates exactly (a backend may pick kernels for that; never correctness).
  bool integer_coordinates = false;
  /// The smallest nonzero |coordinate| of the scaled points (infinity when there is none).
  double smallest_nonzero = std::numeric_limits<double>::infinity();

  /// p multiplied by 2^scale_exponent: exact, one rounding as ldexp does.
  Point2 scaled(const Point2& p) const {
    if (scale_exponent <= 1023) return {p.x * factor, p.y * factor};
    return {std::ldexp(p.x, scale_exponent), std::ldexp(p.y, scale_exponent)};
  }
};

struct SiteSet {
  /// Distinct sites multiplied by 2^scale_exponent (exact), in Morton order: sites near in the
  /// plane are near in memory, so every later stage walks memory mostly in order.
  HostVector<Point2> points;
  /// site -> input index of the point it represents (its first occurrence).
  HostVector<std::int32_t> input_index;
  /// input index -> input index of its representative (a std::vector: it becomes
  /// Mesh::representative).
  std::vector<std::int32_t> representative;
  /// Power of two the input was scaled by, so that the largest |coordinate| lies in [0.5, 1).
  int scale_exponent = 0;
  Box bounds;  ///< of the scaled sites
  bool integer_coordinates = false;  ///< as InputScan::integer_coordinates

  std::int32_t size() const { return static_cast<std::int32_t>(points.size()); }
};

/// Validates (NaN/Inf -> Error(invalid_input) naming the input index; above 2^31 - 1 points
/// Error(too_large)) and finds the scale and the box: prepare_sites' first pass, alone for a
/// backend that sorts and merges on its device.
InputScan scan_input(std::span<const Point2> input);

/// Whether the apex filters are exact on these sites (predicates/exact_lattice.hpp): integer
/// inputs spanning at most 5000 units 2^scale_exponent.
inline bool exact_lattice_arithmetic(const SiteSet& sites) {
  if (sites.points.empty()) return false;
  const Box& box = sites.bounds;
  return exact_lattice_arithmetic(sites.integer_coordinates, sites.scale_exponent,
                                  std::max(box.max_x - box.min_x, box.max_y - box.min_y));
}

/// Validates (NaN/Inf -> Error(invalid_input) naming the input index), scales by a power of
/// two, sorts in Morton order and merges exact duplicates (the smallest input index represents
/// each group). Throws Error(too_large) above 2^31 - 1 points.
SiteSet prepare_sites(std::span<const Point2> input);

}  // namespace expanse::detail
