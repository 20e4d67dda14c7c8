#pragma once
#include <cstddef>

#include "backends/vulkan/vk_context.hpp"

namespace expanse::detail::vk {

// The per-site layout's buffers, kept between calls by the context (BufferCache): every
// Backend on it shares them, so the free function expanse::triangulate, which makes a
// Backend per call, allocates nothing after its first call either (allocating them cost
// 325-365 ms at 4096^2 on the H100, on every call). Host-visible only where a CPU device
// works in place; GPUs stage through the context's fixed StagingRing.
enum Kept : std::size_t {
  k_input_sites, k_input_predecessor, k_cell_key, k_cursor, k_unordered, k_to_sorted,
  k_scan_sums, k_sites, k_cell_start, k_predecessor, k_to_site, k_triangles, k_counters,
  k_stars, k_site_info, k_neighbors, k_unresolved, k_open_slots, k_words,
  // The preparation's (device_preparation.hpp); it leaves the sites in k_input_sites and the
  // hull predecessors in k_input_predecessor.
  k_prep_raw, k_prep_keys0, k_prep_keys1, k_prep_values0, k_prep_values1, k_prep_sorted,
  k_prep_first, k_prep_heads, k_prep_head_sums, k_prep_counts, k_prep_count_sums,
  k_prep_site_input, k_prep_rank, k_prep_representative, k_prep_hull_input, k_prep_hull_sites,
  k_prep_counters, k_cell_bounds, k_sites_to_host
};
inline Buffer& kept(Context& ctx, Kept slot, VkDeviceSize bytes, bool host_visible) {
  return ctx.buffers().get(slot, bytes, host_visible);
}

}  // namespace expanse::detail::vk
