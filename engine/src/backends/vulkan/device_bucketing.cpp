// The star grid's bucketing on the device (see device_bucketing.hpp and shaders/bucket.comp).
#include "backends/vulkan/device_bucketing.hpp"

#include <algorithm>

#include "backends/vulkan/shader_registry.hpp"

namespace expanse::detail::vk {
namespace {

// bucket.comp's push constants and passes.
struct BucketParams {
  double origin[2];
  double inv_width[2];
  std::int32_t cells;
  std::int32_t count;
  std::int32_t first;
  std::int32_t pass;
  std::int32_t triangle_capacity;
  std::int32_t pad[3];
};
static_assert(sizeof(BucketParams) == 64);
enum BucketPass : std::int32_t { pass_count = 0, pass_scatter, pass_order, pass_predecessor, pass_restore };

// Largest cell bucket.comp ranks: the rank loop must stay well under lavapipe's 65535 back
// edges per SIMD batch; more sites in one cell and the host buckets instead.
constexpr std::uint32_t max_ranked_cell = 4096;

}  // namespace

DeviceBucketing::DeviceBucketing(Context& context, std::uint32_t workgroup, bool quantile_cells)
    : context_(context), workgroup_(workgroup), scan_(context, "scan") {
  const std::uint32_t bucket_spec[] = {workgroup_, max_ranked_cell, quantile_cells ? 1u : 0u};
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

// Dispatches `count` invocations in pieces of at most maxComputeWorkGroupCount groups; `first`
// is the push constant that tells each piece where it starts.
void DeviceBucketing::dispatch_over(Recording& rec, Kernel& kernel, void* params,
                                    std::int32_t& first, std::size_t count) {
  const std::size_t max_groups = context_.limits().maxComputeWorkGroupCount[0];
  for (std::size_t at = 0; at < count; at += max_groups * workgroup_) {
    first = std::int32_t(at);
    const std::size_t groups = std::min((count - at + workgroup_ - 1) / workgroup_, max_groups);
    rec.dispatch(kernel, params, std::uint32_t(groups));
  }
}

void DeviceBucketing::record_sort(Recording& rec, const GridShape& grid, std::size_t sites) {
  const std::size_t cells = std::size_t(grid.cells) * std::size_t(grid.cells);
  rec.fill(*cell_start_, 0);
  rec.fill(*counters_, 0);
  rec.barrier();
  BucketParams params{{grid.origin[0], grid.origin[1]},
                      {grid.inv_width[0], grid.inv_width[1]},
                      grid.cells, std::int32_t(sites), 0, pass_count, 0, {0, 0, 0}};
  dispatch_over(rec, *bucket_, &params, params.first, sites);
  rec.barrier();
  scan_.record(rec, cells + 1);
  rec.copy(*cell_start_, *cursor_, VkDeviceSize(cells) * 4);
  rec.barrier();
  for (BucketPass pass : {pass_scatter, pass_order, pass_predecessor}) {
    params.pass = pass;
    dispatch_over(rec, *bucket_, &params, params.first, sites);
    rec.barrier();
  }
}

void DeviceBucketing::record_restore(Recording& rec, std::size_t sites,
                                     std::size_t triangle_capacity) {
  BucketParams params{{0, 0}, {0, 0}, 0, std::int32_t(sites), 0, pass_restore,
                      std::int32_t(triangle_capacity), {0, 0, 0}};
  dispatch_over(rec, *bucket_, &params, params.first, 3 * triangle_capacity);
  rec.barrier();
}

}  // namespace expanse::detail::vk
