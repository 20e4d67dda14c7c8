#pragma once
// The per-site layout on the Vulkan backend (shaders/star.comp, star_links.comp).
#include "backends/backend.hpp"
#include "backends/vulkan/site_preparation.hpp"
#include "backends/vulkan/tuning.hpp"
#include "backends/vulkan/vk_context.hpp"

namespace expanse::detail::vk {

/// Grows every site's star into result. From prepare_on_device (site_copy not null): the sites
/// are in k_input_sites and the hull predecessors in k_input_predecessor (nothing to upload for
/// the device's bucketing), and on the host only their sample until site_copy has run, which
/// this starts beside the stars.
void grow_stars(Context& ctx, const Tuning& tuning, const GrowInput& input, GrowResult& result,
                SiteCopy* site_copy = nullptr);

}  // namespace expanse::detail::vk
