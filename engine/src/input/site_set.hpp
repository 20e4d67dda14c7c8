#pragma once
// Validated, normalised, duplicate-free input: what every backend and the seam stage work on.
#include <cstdint>
#include <span>
#include <vector>

#include "expanse/types.hpp"
#include "input/parallel.hpp"

namespace expanse::detail {

struct Box {
  double min_x = 0, min_y = 0, max_x = 0, max_y = 0;
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

  std::int32_t size() const { return static_cast<std::int32_t>(points.size()); }
};

/// Validates (NaN/Inf -> Error(invalid_input) naming the input index), scales by a power of
/// two, sorts in Morton order and merges exact duplicates (the smallest input index represents
/// each group). Throws Error(too_large) above 2^31 - 1 points.
SiteSet prepare_sites(std::span<const Point2> input);

}  // namespace expanse::detail
