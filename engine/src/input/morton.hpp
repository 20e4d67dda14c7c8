#pragma once
// Quantisation and Morton (Z-order) codes shared by the bucket tree and the spatial sort.
// Quantisation is monotone in the real coordinates, which is what makes integer box tests safe.
#include <cstdint>
#include <vector>

#include "input/site_set.hpp"

namespace expanse::detail {

struct Quantiser {
  static constexpr int bits = 30;
  static constexpr std::uint32_t max = (1u << bits) - 1;

  double origin_x = 0, origin_y = 0, scale = 1;

  /// A square domain over `box`, so squares in quanta are squares in the plane.
  explicit Quantiser(const Box& box);
  std::uint32_t x(double v) const { return clamp((v - origin_x) * scale); }
  std::uint32_t y(double v) const { return clamp((v - origin_y) * scale); }

 private:
  static std::uint32_t clamp(double q) {
    if (!(q > 0.0)) return 0;
    if (q >= static_cast<double>(max)) return max;
    return static_cast<std::uint32_t>(q);
  }
};

/// Interleaves x (even bits) and y (odd bits).
std::uint64_t morton_code(std::uint32_t qx, std::uint32_t qy);

/// Sorts (codes, values) by code, stably (LSD radix sort).
void sort_by_code(std::vector<std::uint64_t>& codes, std::vector<std::int32_t>& values);


}  // namespace expanse::detail
