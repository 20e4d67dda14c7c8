// The star grid's bucketing on the device (see device_bucketing.hpp and shaders/bucket.comp).
#include "backends/vulkan/device_bucketing.hpp"

#include <algorithm>

#include "backends/vulkan/dispatch.hpp"
#include "backends/vulkan/shader_registry.hpp"
#include "host_device.h"

namespace expanse::detail::vk {
namespace {

using namespace shared;

// Largest cell bucket.comp ranks: the rank loop must stay well under lavapipe's 65535 back
// edges per SIMD batch; more sites in one cell and the host buckets instead.
constexpr std::uint32_t max_ranked_cell = 4096;

}  // namespace

DeviceBucketing::DeviceBucketing(Context& context, std::uint32_t workgroup, bool quantile_cells)
    : context_(context), workgroup_(workgroup), scan_(context, "scan") {
  std::uint32_t bucket_spec[BUCKET_SPEC_COUNT];
  bucket_spec[BUCKET_SPEC_WORKGROUP] = workgroup_;
  bucket_spec[BUCKET_SPEC_MAX_CELL] = max_ranked_cell;
  bucket_spec[BUCKET_SPEC_QUANTILE_CELLS] = quantile_cells;
  bucket_ = &context.kernel("bucket", spirv::bucket(), 13, sizeof(BucketParams), bucket_spec);
}

VkDeviceSize DeviceBucketing::scan_sums_bytes(std::size_t count) const { return scan_.sums_bytes(count); }

void DeviceBucketing::bind(const BucketingBuffers& b) {
  Buffer* bucket_bindings[] = {b.input_sites, b.input_predecessor, b.cell_key,  b.cell_start,
                               b.cursor,      b.unordered,         b.sorted_sites, b.to_site,
                               b.to_sorted,   b.predecessor,       b.triangles, b.counters,
                               b.cell_bounds};
  bucket_->bind(bucket_bindings);
  scan_.bind(*b.cell_start, *b.scan_sums);
  cell_start_ = b.cell_start;
  cursor_ = b.cursor;
  counters_ = b.counters;
}

void DeviceBucketing::record_sort(Recording& rec, const GridShape& grid, std::size_t sites) {
  const std::size_t cells = std::size_t(grid.cells) * std::size_t(grid.cells);
  rec.fill(*cell_start_, 0);
  rec.fill(*counters_, 0);
  rec.barrier();
  BucketParams params{{grid.origin[0], grid.origin[1]}, {grid.inv_width[0], grid.inv_width[1]},
                      grid.cells, int(sites), 0, BUCKET_PASS_COUNT, 0, 0, 0, 0};
  dispatch_over(context_, rec, *bucket_, params, params.first, sites, workgroup_);
  rec.barrier();
  scan_.record(rec, cells + 1);
  rec.copy(*cell_start_, *cursor_, VkDeviceSize(cells) * 4);
  rec.barrier();
  for (int pass : {BUCKET_PASS_SCATTER, BUCKET_PASS_ORDER, BUCKET_PASS_PREDECESSOR}) {
    params.pass = pass;
    dispatch_over(context_, rec, *bucket_, params, params.first, sites, workgroup_);
    rec.barrier();
  }
}

void DeviceBucketing::record_restore(Recording& rec, std::size_t sites,
                                     std::size_t triangle_capacity) {
  BucketParams params{{0, 0}, {0, 0}, 0, int(sites), 0, BUCKET_PASS_RESTORE, int(triangle_capacity), 0, 0, 0};
  dispatch_over(context_, rec, *bucket_, params, params.first, 3 * triangle_capacity, workgroup_);
  rec.barrier();
}

}  // namespace expanse::detail::vk
