#pragma once
// The pipeline's last step: site ids back to the caller's input indices.
#include <cstdint>
#include <span>
#include <vector>

#include "expanse/types.hpp"
#include "input/site_set.hpp"

namespace expanse::detail {

/// Replaces every site id v in `triangles` by sites.input_index[v], in place.
void remap_to_input(std::span<Triangle> triangles, const SiteSet& sites);
inline void remap_to_input(std::vector<Triangle>& triangles, const SiteSet& sites) {
  remap_to_input(std::span<Triangle>(triangles), sites);
}

/// sites.input_index[s] for each s of `site_ids`.
std::vector<std::int32_t> to_input_indices(const std::vector<std::int32_t>& site_ids, const SiteSet& sites);

}  // namespace expanse::detail
