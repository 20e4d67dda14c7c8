#pragma once
// When the apex searches' floating-point filters are exact: small integer lattices, whose
// cocircular cells otherwise send most candidates of a search to the exact path. The CUDA
// kernel and the Vulkan star shader then decide every candidate in the scan.
#include <algorithm>
#include <cmath>

#include "input/site_set.hpp"

namespace expanse::detail {

/// Whether the apex filters' arithmetic (apex_filter.hpp, and predicates.glsl's transcription)
/// is exact on these sites, so that a search needs no exact path: integer inputs (scaled by
/// 2^e, each coordinate an integer number of units 2^e) spanning at most 5000 units on either
/// axis. Then every coordinate difference is an exact integer of at most D = 5000 units, the
/// lifts' values stay below 4 D^3 and the incircle value and its partial sums below 12 D^4 <
/// 2^53 units^4 (D^4 units^4 well above the smallest double for any e the scaling picks): each
/// operation's result is representable, so each is exact, fused or not. A 4096^2 lattice qualifies; its cocircular cells took most candidates of a
/// search to the exact path (13 a site on 1M sites, counted on the CPU).
inline bool exact_lattice_arithmetic(const SiteSet& sites) {
  if (!sites.integer_coordinates || sites.points.empty()) return false;
  const double unit = std::ldexp(1.0, sites.scale_exponent);
  const double span = std::max(sites.bounds.max_x - sites.bounds.min_x, sites.bounds.max_y - sites.bounds.min_y);
  return unit > 0.0 && span <= 5000.0 * unit;
}

}  // namespace expanse::detail
