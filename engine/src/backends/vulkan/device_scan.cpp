// Prefix sums on the device (see device_scan.hpp and shaders/scan.comp).
#include "backends/vulkan/device_scan.hpp"

#include <algorithm>

#include "backends/vulkan/shader_registry.hpp"

namespace expanse::detail::vk {
namespace {

// scan.comp's push constants and passes.
struct ScanParams {
  std::int32_t count;
  std::int32_t offset;
  std::int32_t level_in_sums;
  std::int32_t sums_offset;
  std::int32_t first_tile;
  std::int32_t pass;
  std::int32_t pad[2];
};
static_assert(sizeof(ScanParams) == 32);
enum ScanPass : std::int32_t { pass_tiles = 0, pass_add };
constexpr std::size_t scan_per_thread = 4;  // scan.comp's PER_THREAD

}  // namespace

DeviceScan::DeviceScan(Context& context, const std::string& name) : context_(context) {
  const auto& limits = context.limits();
  workgroup_ = std::max(1u, std::min({256u, limits.maxComputeWorkGroupSize[0],
                                      limits.maxComputeWorkGroupInvocations}));
  const std::uint32_t spec[] = {workgroup_};
  kernel_ = &context.kernel(name, spirv::scan(), 2, sizeof(ScanParams), spec);
}

VkDeviceSize DeviceScan::sums_bytes(std::size_t count) const {
  const std::size_t tile = scan_per_thread * workgroup_;
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
  const std::size_t tile = scan_per_thread * workgroup_;
  const std::size_t tiles = (count + tile - 1) / tile;
  const std::size_t max_groups = context_.limits().maxComputeWorkGroupCount[0];
  ScanParams params{std::int32_t(count), std::int32_t(offset), in_sums ? 1 : 0,
                    std::int32_t(sums_offset), 0, pass_tiles, {0, 0}};
  auto each_tile = [&] {
    for (std::size_t first = 0; first < tiles; first += max_groups) {
      params.first_tile = std::int32_t(first);
      rec.dispatch(*kernel_, &params, std::uint32_t(std::min(tiles - first, max_groups)));
    }
  };
  each_tile();
  rec.barrier();
  if (tiles <= 1) return;
  record_level(rec, tiles, sums_offset, true, sums_offset + tiles);
  params.pass = pass_add;
  each_tile();
  rec.barrier();
}

}  // namespace expanse::detail::vk
