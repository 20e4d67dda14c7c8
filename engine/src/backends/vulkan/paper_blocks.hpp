#pragma once
// The paper's layout on the Vulkan backend (shaders/blocks.comp): a seed per block, each block
// grown by one workgroup.
#include "backends/backend.hpp"
#include "backends/vulkan/tuning.hpp"
#include "backends/vulkan/vk_context.hpp"

namespace expanse::detail::vk {

/// Grows input.layout's blocks (Layout::Seeding::paper_blocks) into result.
void grow_blocks(Context& ctx, const Tuning& tuning, const GrowInput& input, GrowResult& result);

}  // namespace expanse::detail::vk
