#pragma once
// The star grid's bucketing on the device: shaders/bucket.comp and shaders/scan.comp recorded
// into a Recording. The host uploads the sites and the hull's predecessors in SiteSet order;
// the device sorts them into cells (SiteSet order within a cell, as the host's counting sort),
// and after the star kernel maps the triangles back to SiteSet ids.
#include <cstddef>
#include <cstdint>

#include "backends/vulkan/device_scan.hpp"
#include "backends/vulkan/vk_context.hpp"

namespace expanse::detail::vk {

/// A cells x cells grid: cell_coord's origin and scale (shaders/include/cells.glsl).
struct GridShape {
  double origin[2]{}, inv_width[2]{};
  int cells = 0;
};

/// The buffers bucket.comp reads and writes (its bindings, in order).
struct BucketingBuffers {
  Buffer* input_sites;        // n dvec2, SiteSet order (uploaded)
  Buffer* input_predecessor;  // n int: hull.predecessor, SiteSet ids (uploaded)
  Buffer* cell_key;           // n int, scratch
  Buffer* cell_start;         // cells^2 + 1 int: the star kernel's cell starts
  Buffer* cursor;             // cells^2 int, scratch
  Buffer* unordered;          // n int, scratch
  Buffer* sorted_sites;       // n dvec2: the star kernel's sites
  Buffer* to_site;            // n int: sorted id -> SiteSet id
  Buffer* to_sorted;          // n int, scratch
  Buffer* predecessor;        // n int: hull predecessors in sorted ids, for the star kernel
  Buffer* triangles;          // star kernel output, mapped back in place
  Buffer* counters;           // star kernel counters: COUNTER_CROWDED_CELL, COUNTER_INVALID_ID set here
  Buffer* scan_sums;          // scan_sums_bytes(cells^2 + 1)
  Buffer* cell_bounds;        // quantile cells' boundaries (star_cells.hpp); any buffer else
};

class DeviceBucketing {
 public:
  /// Compiles (once per context) the two kernels with `workgroup` invocations per group, for
  /// uniform cells (cells.glsl) or quantile cells (quantile_cells.glsl).
  DeviceBucketing(Context& context, std::uint32_t workgroup, bool quantile_cells);
  /// Bytes scan.comp needs beside `count` elements for its tile totals, at every level.
  VkDeviceSize scan_sums_bytes(std::size_t count) const;
  /// Points the kernels at these buffers; only between submissions.
  void bind(const BucketingBuffers& buffers);
  /// Records the sort of `sites` sites into the grid: fills cell_start, sorted_sites, to_site
  /// and predecessor, and zeroes counters (COUNTER_CROWDED_CELL: a cell too large to rank).
  /// Needs input_sites and input_predecessor written (and visible: a barrier after the upload).
  void record_sort(Recording& rec, const GridShape& grid, std::size_t sites);
  /// Records the mapping of the star kernel's triangles (at most triangle_capacity, counted in
  /// counters[COUNTER_TRIANGLES]) from sorted ids to SiteSet ids; an id out of range sets
  /// counters[COUNTER_INVALID_ID].
  void record_restore(Recording& rec, std::size_t sites, std::size_t triangle_capacity);

 private:
  Context& context_;
  std::uint32_t workgroup_;
  Kernel* bucket_ = nullptr;
  DeviceScan scan_;
  Buffer* cell_start_ = nullptr;
  Buffer* cursor_ = nullptr;
  Buffer* counters_ = nullptr;
};

}  // namespace expanse::detail::vk
