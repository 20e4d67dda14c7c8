#pragma once
// Bucketing and star bookkeeping shared by both layouts.
#include <cstdint>

#include "device_geometry.cuh"

namespace expanse::detail::cuda {

/// Stars hold at most this many neighbours (a power of two); a site with more defers (the seam
/// stage makes its triangles). 16 was too few: sites on the flat hull sides of uniform inputs
/// fan out to many hull-hugging neighbours, and 14 of 10^6 uniform sites deferred, each deferral
/// sending the whole pipeline through the seam stage (counted with bench/src/star_work.cpp).
inline constexpr int kStar = 32;
inline constexpr std::uint32_t kClosedBit = 1u << 16;
inline constexpr std::uint32_t kDeferredBit = 1u << 17;

EXPANSE_DEVICE_FORCE int star_degree(std::uint32_t info) { return static_cast<int>(info & 255u); }
EXPANSE_DEVICE_FORCE int star_start(std::uint32_t info) { return static_cast<int>((info >> 8) & 255u); }
EXPANSE_DEVICE_FORCE bool star_closed(std::uint32_t info) { return (info & kClosedBit) != 0; }
EXPANSE_DEVICE_FORCE bool star_deferred(std::uint32_t info) { return (info & kDeferredBit) != 0; }

/// t-th neighbour of site o in CCW order, t in [-1, deg + 1] (wrapping, for closed stars). The
/// wrap by comparisons, not `%`: an integer remainder is ~20 instructions on the GPU, and the
/// emit kernel wraps twice for every entry of every star it searches.
EXPANSE_DEVICE_FORCE int star_at(const int* star, std::uint32_t info, int o, int t) {
  const int deg = star_degree(info);
  t = t < 0 ? t + deg : t;
  t = t >= deg ? t - deg : t;
  t = t >= deg ? t - deg : t;  // deg 1, t = 2
  return star[static_cast<std::size_t>(o) * kStar + ((star_start(info) + t) & (kStar - 1))];
}

EXPANSE_DEVICE_FORCE int star_find(const int* star, std::uint32_t info, int o, int u) {
  const int deg = star_degree(info);
  for (int t = 0; t < deg; ++t)
    if (star_at(star, info, o, t) == u) return t;
  return -1;
}

}  // namespace expanse::detail::cuda
