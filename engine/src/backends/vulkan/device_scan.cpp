// Prefix sums on the device (see device_scan.hpp and shaders/scan.comp).
#include "backends/vulkan/device_scan.hpp"

#include <algorithm>

#include "backends/vulkan/dispatch.hpp"
#include "backends/vulkan/shader_registry.hpp"
#include "host_device.h"

namespace expanse::detail::vk {
using namespace shared;

DeviceScan::DeviceScan(Context& context, const std::string& name) : context_(context) {
  const auto& limits = context.limits();
  workgroup_ = std::max(1u, std::min({256u, limits.maxComputeWorkGroupSize[0],
                                      limits.maxComputeWorkGroupInvocations}));
  const std::uint32_t spec[] = {workgroup_};
  kernel_ = &context.kernel(name, spirv::scan(), 2, sizeof(ScanParams), spec);
}

VkDeviceSize DeviceScan::sums_bytes(std::size_t count) const {
  const std::size_t tile = std::size_t(SCAN_PER_THREAD) * workgroup_;
  std::size_t total = 0;
  do {
    count = (count + tile - 1) / tile;  // one total per tile of this level
    total += count;
  } while (count > 1);
  return VkDeviceSize(total) * 4;
}

void DeviceScan::bind(Buffer& data, Buffer& sums) {
  Buffer* bindings[] = {&data, &sums};
  kernel_->bind(bindings);
}

// Inclusive scan of `count` ints at `offset` (of the data, or of the sums when in_sums), tile
// totals at sums_offset of the sums; the levels above are scanned recursively.
void DeviceScan::record_level(Recording& rec, std::size_t count, std::size_t offset, bool in_sums,
                              std::size_t sums_offset) {
  const std::size_t tile = std::size_t(SCAN_PER_THREAD) * workgroup_;
  const std::size_t tiles = (count + tile - 1) / tile;
  ScanParams params{int(count), int(offset), in_sums ? 1 : 0, int(sums_offset), 0, SCAN_PASS_TILES, 0, 0};
  // One workgroup a tile.
  auto each_tile = [&] { dispatch_over(context_, rec, *kernel_, params, params.first_tile, tiles, 1); };
  each_tile();
  rec.barrier();
  if (tiles <= 1) return;
  record_level(rec, tiles, sums_offset, true, sums_offset + tiles);
  params.pass = SCAN_PASS_ADD;
  each_tile();
  rec.barrier();
}

}  // namespace expanse::detail::vk
