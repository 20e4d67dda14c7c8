#pragma once
// The site preparation on the device: shaders/prepare_sites.comp, radix_sort.comp and scan.comp
// recorded into Recordings. The host uploads the raw points; the device scales them, sorts them
// in Morton order, merges duplicates and compacts the sites, as prepare_sites does on the host
// (the CUDA backend's prepare_on_device.cu, in GLSL), and maps the host's hull to site ids.
#include <cstddef>
#include <cstdint>

#include "backends/vulkan/device_scan.hpp"
#include "backends/vulkan/vk_context.hpp"
#include "host_device.h"

namespace expanse::detail::vk {

/// The buffers prepare_sites.comp and radix_sort.comp read and write; n is the input's size.
struct PreparationBuffers {
  Buffer* raw;             // n dvec2: the input (uploaded), scaled in place
  Buffer* keys[2];         // n uvec2 each: sort keys, two sides
  Buffer* values[2];       // n int each: input indices, two sides
  Buffer* sorted;          // n dvec2: the points in sorted order
  Buffer* first;           // n int: the first position of each one's group of equal points
  Buffer* heads;           // n int: group starts, then their inclusive scan
  Buffer* head_sums;       // head_sums_bytes(n)
  Buffer* counts;          // counts_bytes(n): the radix sort's digit counts per tile
  Buffer* count_sums;      // count_sums_bytes(n)
  Buffer* site_points;     // n dvec2: the sites, in Morton order
  Buffer* site_input;      // n int: site -> input index
  Buffer* rank;            // n int: input index -> site
  Buffer* representative;  // n int: input index -> its group's first input index
  Buffer* hull_input;      // the hull's input indices (bind again once they are known)
  Buffer* hull_sites;      // the hull in site ids
  Buffer* predecessor;     // n int: hull predecessors in site ids, -1 elsewhere
  Buffer* counters;        // 64 bytes: PREPARE_COUNTER_LONG_RUN, PREPARE_COUNTER_SITES
};

/// How the points are scaled and quantised: p * factor * second_factor (powers of two, each
/// multiplication exact), then the Quantiser's origin and scale.
struct PreparationScale {
  double origin[2]{};
  double scale = 1.0;
  double factor = 1.0, second_factor = 1.0;
};

class DevicePreparation {
 public:
  /// Compiles (once per context) the kernels with `workgroup` invocations per group.
  DevicePreparation(Context& context, std::uint32_t workgroup);
  VkDeviceSize counts_bytes(std::size_t n) const;
  VkDeviceSize count_sums_bytes(std::size_t n) const;
  VkDeviceSize head_sums_bytes(std::size_t n) const;
  /// Points the kernels at these buffers; only between submissions.
  void bind(const PreparationBuffers& buffers);
  /// Records: scale, Morton codes, the sort by code (stable), the points in that order, and
  /// the search for equal points through runs of equal codes. A nonzero
  /// counters[PREPARE_COUNTER_LONG_RUN] afterwards: a run was too long to search, and
  /// record_sort_by_point must follow.
  void record_sort(Recording& rec, std::size_t n, const PreparationScale& scale);
  /// Records the sort by (code, x, y), which puts equal points side by side, and their groups.
  void record_sort_by_point(Recording& rec, std::size_t n);
  /// Records the compaction of the groups' first points into the sites
  /// (counters[PREPARE_COUNTER_SITES]: how many), the input-to-site map and the representatives.
  void record_compact(Recording& rec, std::size_t n);
  /// Records the hull's input indices (hull_input) -> site ids (hull_sites), and predecessor.
  void record_hull(Recording& rec, std::size_t hull_count);
  /// Records the copy of `count` sites, every stride-th, into the start of `sorted`.
  void record_sample(Recording& rec, std::size_t count, std::size_t stride);

 private:
  void dispatch_prepare(Recording& rec, shared::PrepareParams& params, int pass, std::size_t count);
  void record_radix(Recording& rec, std::size_t n, int bits);
  Context& context_;
  std::uint32_t workgroup_, sort_workgroup_;
  Kernel* prepare_ = nullptr;
  Kernel* radix_ = nullptr;
  DeviceScan count_scan_, head_scan_;
  Buffer* predecessor_ = nullptr;
  Buffer* counters_ = nullptr;
  PreparationScale scale_;
  int side_ = 0;  // where the sorted keys and values are
  bool heads_scanned_ = false;
};

}  // namespace expanse::detail::vk
