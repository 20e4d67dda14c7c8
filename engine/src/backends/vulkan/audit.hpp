#pragma once
// The device audit of the per-site layout's adjacency (shaders/audit.comp).
#include <cstddef>
#include <cstdint>

#include "backends/vulkan/vk_context.hpp"

namespace expanse::detail::vk {

/// Records audit.comp over the first counters[COUNTER_TRIANGLES] (at most `capacity`)
/// triangles, in SiteSet ids, and their links; `predecessor` is hull.predecessor. Binds the
/// kernel: between submissions only.
void record_audit(Context& ctx, Recording& rec, std::uint32_t wg, Buffer& triangles, Buffer& neighbors,
                  Buffer& predecessor, Buffer& open_slots, Buffer& counters, std::size_t capacity,
                  std::size_t open_capacity);

}  // namespace expanse::detail::vk
