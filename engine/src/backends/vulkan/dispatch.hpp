#pragma once
#include <algorithm>
#include <cstdint>

#include "backends/vulkan/vk_context.hpp"

namespace expanse::detail::vk {

/// Records dispatches of `kernel` over `count` invocations in workgroups of `wg`, split to
/// respect maxComputeWorkGroupCount: `first` (a field of `params`, the push constants) tells
/// each dispatch its first invocation.
template <class Params>
void dispatch_over(Context& ctx, Recording& rec, Kernel& kernel, Params& params, int& first,
                   std::uint64_t count, std::uint32_t wg) {
  const std::uint64_t max_groups = ctx.limits().maxComputeWorkGroupCount[0];
  for (std::uint64_t at = 0; at < count; at += max_groups * wg) {
    first = int(at);
    const std::uint64_t left = (count - at + wg - 1) / wg;
    rec.dispatch(kernel, &params, std::uint32_t(std::min(left, max_groups)));
  }
}

}  // namespace expanse::detail::vk
