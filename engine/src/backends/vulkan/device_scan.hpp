#pragma once
// Inclusive prefix sums of int32 on the device (shaders/scan.comp), recorded level by level into
// a Recording: each tile of 4 x workgroup elements is scanned and its total stored a level up,
// the totals are scanned the same way, and each tile adds the totals before it.
#include <cstddef>
#include <cstdint>
#include <string>

#include "backends/vulkan/vk_context.hpp"

namespace expanse::detail::vk {

class DeviceScan {
 public:
  /// Compiles (once per context, under `name`: each name has its own descriptor set, so scans
  /// of different buffers may share one recording) scan.comp.
  DeviceScan(Context& context, const std::string& name);
  /// Bytes the tile totals of `count` elements need, at every level.
  VkDeviceSize sums_bytes(std::size_t count) const;
  /// The buffer to scan and the one for the tile totals (sums_bytes); only between submissions.
  void bind(Buffer& data, Buffer& sums);
  /// Records the scan of the first `count` ints of the bound buffer, in place, and a barrier.
  void record(Recording& rec, std::size_t count) { record_level(rec, count, 0, false, 0); }

 private:
  void record_level(Recording& rec, std::size_t count, std::size_t offset, bool in_sums,
                    std::size_t sums_offset);
  Context& context_;
  std::uint32_t workgroup_;
  Kernel* kernel_ = nullptr;
};

}  // namespace expanse::detail::vk
