#pragma once
// When the apex searches' floating-point filters are exact: small integer lattices, whose
// cocircular cells otherwise send most candidates of a search to the exact path. The CUDA
// kernel and the Vulkan star shader then decide every candidate in the scan. The test on a
// SiteSet is exact_lattice_arithmetic(const SiteSet&) in input/site_set.hpp.
#include <cmath>

namespace expanse::detail {

/// Whether the apex filters' arithmetic (apex_filter.hpp, and predicates.glsl's transcription)
/// is exact on sites scaled by 2^scale_exponent whose coordinates are all integers (before
/// scaling) and whose box spans `span` (scaled) on its longer side: integer inputs, each
/// coordinate an integer number of units 2^scale_exponent, spanning at most 5000 units. Then
/// every coordinate difference is an exact integer of at most D = 5000 units, the lifts' values
/// stay below 4 D^3 and the incircle value and its partial sums below 12 D^4 < 2^53 units^4
/// (D^4 units^4 well above the smallest double for any exponent the scaling picks): each
/// operation's result is representable, so each is exact, fused or not. A 4096^2 lattice
/// qualifies; its cocircular cells took most candidates of a search to the exact path (13 a
/// site on 1M sites, counted on the CPU).
inline bool exact_lattice_arithmetic(bool integer_coordinates, int scale_exponent, double span) {
  if (!integer_coordinates) return false;
  const double unit = std::ldexp(1.0, scale_exponent);
  return unit > 0.0 && span <= 5000.0 * unit;
}

}  // namespace expanse::detail
