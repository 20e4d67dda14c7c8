// The site preparation on the device (see device_preparation.hpp, shaders/prepare_sites.comp
// and shaders/radix_sort.comp).
#include "backends/vulkan/device_preparation.hpp"

#include <algorithm>

#include "backends/vulkan/dispatch.hpp"
#include "backends/vulkan/shader_registry.hpp"

namespace expanse::detail::vk {
namespace {

using namespace shared;

constexpr std::size_t radix_items = RADIX_ITEMS, radix_digits = RADIX_DIGITS;
constexpr int radix_bits = 4;
static_assert(RADIX_DIGITS == 1 << radix_bits);

// Bits of the sort keys: the Morton code (Quantiser::bits per coordinate), a coordinate's bits.
constexpr int code_bits = 60, coordinate_bits = 64;

}  // namespace


DevicePreparation::DevicePreparation(Context& context, std::uint32_t workgroup)
    : context_(context),
      workgroup_(workgroup),
      count_scan_(context, "prepare: digit counts scan"),
      head_scan_(context, "prepare: group scan") {
  const auto& limits = context.limits();
  sort_workgroup_ = std::max(1u, std::min({256u, limits.maxComputeWorkGroupSize[0],
                                           limits.maxComputeWorkGroupInvocations}));
  const std::uint32_t prepare_spec[] = {workgroup_};
  prepare_ = &context.kernel("prepare_sites", spirv::prepare_sites(), 16, sizeof(PrepareParams), prepare_spec);
  const std::uint32_t radix_spec[] = {sort_workgroup_};
  radix_ = &context.kernel("radix_sort", spirv::radix_sort(), 5, sizeof(RadixParams), radix_spec);
}

VkDeviceSize DevicePreparation::counts_bytes(std::size_t n) const {
  const std::size_t tile = radix_items * sort_workgroup_;
  return VkDeviceSize(radix_digits * std::max<std::size_t>(1, (n + tile - 1) / tile)) * 4;
}

VkDeviceSize DevicePreparation::count_sums_bytes(std::size_t n) const {
  return count_scan_.sums_bytes(std::size_t(counts_bytes(n) / 4));
}

VkDeviceSize DevicePreparation::head_sums_bytes(std::size_t n) const { return head_scan_.sums_bytes(n); }

void DevicePreparation::bind(const PreparationBuffers& b) {
  Buffer* prepare_bindings[] = {b.raw,    b.keys[0],     b.keys[1],     b.values[0],
                                b.values[1], b.sorted,   b.first,       b.heads,
                                b.site_points, b.site_input, b.rank,    b.representative,
                                b.hull_input, b.hull_sites, b.predecessor, b.counters};
  prepare_->bind(prepare_bindings);
  Buffer* radix_bindings[] = {b.keys[0], b.keys[1], b.values[0], b.values[1], b.counts};
  radix_->bind(radix_bindings);
  count_scan_.bind(*b.counts, *b.count_sums);
  head_scan_.bind(*b.heads, *b.head_sums);
  predecessor_ = b.predecessor;
  counters_ = b.counters;
}

// One invocation per element, in pieces of at most maxComputeWorkGroupCount groups; a barrier.
void DevicePreparation::dispatch_prepare(Recording& rec, PrepareParams& params, int pass, std::size_t count) {
  params.pass = pass;
  params.count = int(count);
  params.side = side_;
  dispatch_over(context_, rec, *prepare_, params, params.first, count, workgroup_);
  rec.barrier();
}

// The stable sort of the pairs on side_ by the low `bits` bits of their keys, four a pass.
void DevicePreparation::record_radix(Recording& rec, std::size_t n, int bits) {
  const std::size_t tile = radix_items * sort_workgroup_;
  const std::size_t tiles = (n + tile - 1) / tile;
  RadixParams params{int(n), int(tiles), 0, 0, 0, RADIX_PASS_COUNT, 0, 0};
  auto each_tile = [&](int pass) {  // one workgroup a tile
    params.pass = pass;
    dispatch_over(context_, rec, *radix_, params, params.first_tile, tiles, 1);
    rec.barrier();
  };
  for (int shift = 0; shift < bits; shift += radix_bits) {
    params.shift = shift;
    params.side = side_;
    each_tile(RADIX_PASS_COUNT);
    count_scan_.record(rec, radix_digits * tiles);
    each_tile(RADIX_PASS_SCATTER);
    side_ = 1 - side_;
  }
}

void DevicePreparation::record_sort(Recording& rec, std::size_t n, const PreparationScale& scale) {
  scale_ = scale;
  side_ = 0;
  heads_scanned_ = false;
  rec.fill(*counters_, 0);
  rec.barrier();
  PrepareParams params{{scale.origin[0], scale.origin[1]}, scale.scale, scale.factor, scale.second_factor,
                0, 0, 0, 0, 0, 0};
  dispatch_prepare(rec, params, PREPARE_PASS_CODES, n);
  record_radix(rec, n, code_bits);
  dispatch_prepare(rec, params, PREPARE_PASS_GATHER, n);
  dispatch_prepare(rec, params, PREPARE_PASS_FIRST_EQUAL, n);
}

void DevicePreparation::record_sort_by_point(Recording& rec, std::size_t n) {
  // Least significant key first, from the order by (code, input index): equal points end side
  // by side in input order.
  PrepareParams params{{scale_.origin[0], scale_.origin[1]}, scale_.scale, scale_.factor, scale_.second_factor,
                0, 0, 0, 0, 0, 0};
  for (int key : {0, 1, 2}) {
    params.mode = key;
    dispatch_prepare(rec, params, PREPARE_PASS_KEYS, n);
    record_radix(rec, n, key == 2 ? code_bits : coordinate_bits);
  }
  dispatch_prepare(rec, params, PREPARE_PASS_GATHER, n);
  dispatch_prepare(rec, params, PREPARE_PASS_GROUP_START, n);
  head_scan_.record(rec, n);
  dispatch_prepare(rec, params, PREPARE_PASS_HEAD_POSITION, n);
  dispatch_prepare(rec, params, PREPARE_PASS_FIRST_OF_GROUP, n);
  heads_scanned_ = true;
}

void DevicePreparation::record_compact(Recording& rec, std::size_t n) {
  if (!heads_scanned_) head_scan_.record(rec, n);
  PrepareParams params{{0, 0}, 1.0, 1.0, 1.0, 0, 0, 0, 0, 0, 0};
  dispatch_prepare(rec, params, PREPARE_PASS_COMPACT, n);
}

void DevicePreparation::record_hull(Recording& rec, std::size_t hull_count) {
  rec.fill(*predecessor_, 0xFFFFFFFFu);  // -1: not on the hull
  rec.barrier();
  PrepareParams params{{0, 0}, 1.0, 1.0, 1.0, 0, 0, 0, 0, 0, 0};
  dispatch_prepare(rec, params, PREPARE_PASS_HULL, hull_count);
  dispatch_prepare(rec, params, PREPARE_PASS_PREDECESSOR, hull_count);
}

void DevicePreparation::record_sample(Recording& rec, std::size_t count, std::size_t stride) {
  PrepareParams params{{0, 0}, 1.0, 1.0, 1.0, 0, 0, 0, 0, std::int32_t(stride), 0};
  dispatch_prepare(rec, params, PREPARE_PASS_SAMPLE, count);
}

}  // namespace expanse::detail::vk
