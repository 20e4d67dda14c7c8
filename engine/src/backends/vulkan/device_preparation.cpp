// The site preparation on the device (see device_preparation.hpp, shaders/prepare_sites.comp
// and shaders/radix_sort.comp).
#include "backends/vulkan/device_preparation.hpp"

#include <algorithm>

#include "backends/vulkan/shader_registry.hpp"

namespace expanse::detail::vk {
namespace {

// radix_sort.comp's push constants, passes and tile.
struct RadixParams {
  std::int32_t count;
  std::int32_t tiles;
  std::int32_t shift;
  std::int32_t side;
  std::int32_t first_tile;
  std::int32_t pass;
  std::int32_t pad[2];
};
static_assert(sizeof(RadixParams) == 32);
enum RadixPass : std::int32_t { radix_count = 0, radix_scatter };
constexpr std::size_t radix_items = 8, radix_digits = 16;  // ITEMS, RADIX
constexpr int radix_bits = 4;

enum PreparePass : std::int32_t {
  pass_codes = 0, pass_gather, pass_first_equal, pass_keys, pass_group_start, pass_head_position,
  pass_first_of_group, pass_compact, pass_hull, pass_predecessor, pass_sample
};
// Bits of the sort keys: the Morton code (Quantiser::bits per coordinate), a coordinate's bits.
constexpr int code_bits = 60, coordinate_bits = 64;

}  // namespace

// prepare_sites.comp's push constants.
struct DevicePreparation::Params {
  double origin[2];
  double scale;
  double factor;
  double second_factor;
  std::int32_t count;
  std::int32_t pass;
  std::int32_t first;
  std::int32_t side;
  std::int32_t mode;
  std::int32_t pad;
};

DevicePreparation::DevicePreparation(Context& context, std::uint32_t workgroup)
    : context_(context),
      workgroup_(workgroup),
      count_scan_(context, "prepare: digit counts scan"),
      head_scan_(context, "prepare: group scan") {
  const auto& limits = context.limits();
  sort_workgroup_ = std::max(1u, std::min({256u, limits.maxComputeWorkGroupSize[0],
                                           limits.maxComputeWorkGroupInvocations}));
  const std::uint32_t prepare_spec[] = {workgroup_};
  prepare_ = &context.kernel("prepare_sites", spirv::prepare_sites(), 16, sizeof(Params), prepare_spec);
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
void DevicePreparation::dispatch_prepare(Recording& rec, Params& params, int pass, std::size_t count) {
  static_assert(sizeof(Params) == 64, "prepare_sites.comp's push constants");
  params.pass = pass;
  params.count = std::int32_t(count);
  params.side = side_;
  const std::size_t max_groups = context_.limits().maxComputeWorkGroupCount[0];
  for (std::size_t at = 0; at < count; at += max_groups * workgroup_) {
    params.first = std::int32_t(at);
    const std::size_t groups = std::min((count - at + workgroup_ - 1) / workgroup_, max_groups);
    rec.dispatch(*prepare_, &params, std::uint32_t(groups));
  }
  rec.barrier();
}

// The stable sort of the pairs on side_ by the low `bits` bits of their keys, four a pass.
void DevicePreparation::record_radix(Recording& rec, std::size_t n, int bits) {
  const std::size_t tile = radix_items * sort_workgroup_;
  const std::size_t tiles = (n + tile - 1) / tile;
  const std::size_t max_groups = context_.limits().maxComputeWorkGroupCount[0];
  RadixParams params{std::int32_t(n), std::int32_t(tiles), 0, 0, 0, radix_count, {0, 0}};
  auto each_tile = [&](RadixPass pass) {
    params.pass = pass;
    for (std::size_t first = 0; first < tiles; first += max_groups) {
      params.first_tile = std::int32_t(first);
      rec.dispatch(*radix_, &params, std::uint32_t(std::min(tiles - first, max_groups)));
    }
    rec.barrier();
  };
  for (int shift = 0; shift < bits; shift += radix_bits) {
    params.shift = shift;
    params.side = side_;
    each_tile(radix_count);
    count_scan_.record(rec, radix_digits * tiles);
    each_tile(radix_scatter);
    side_ = 1 - side_;
  }
}

void DevicePreparation::record_sort(Recording& rec, std::size_t n, const PreparationScale& scale) {
  scale_ = scale;
  side_ = 0;
  heads_scanned_ = false;
  rec.fill(*counters_, 0);
  rec.barrier();
  Params params{{scale.origin[0], scale.origin[1]}, scale.scale, scale.factor, scale.second_factor,
                0, 0, 0, 0, 0, 0};
  dispatch_prepare(rec, params, pass_codes, n);
  record_radix(rec, n, code_bits);
  dispatch_prepare(rec, params, pass_gather, n);
  dispatch_prepare(rec, params, pass_first_equal, n);
}

void DevicePreparation::record_sort_by_point(Recording& rec, std::size_t n) {
  // Least significant key first, from the order by (code, input index): equal points end side
  // by side in input order.
  Params params{{scale_.origin[0], scale_.origin[1]}, scale_.scale, scale_.factor, scale_.second_factor,
                0, 0, 0, 0, 0, 0};
  for (int key : {0, 1, 2}) {
    params.mode = key;
    dispatch_prepare(rec, params, pass_keys, n);
    record_radix(rec, n, key == 2 ? code_bits : coordinate_bits);
  }
  dispatch_prepare(rec, params, pass_gather, n);
  dispatch_prepare(rec, params, pass_group_start, n);
  head_scan_.record(rec, n);
  dispatch_prepare(rec, params, pass_head_position, n);
  dispatch_prepare(rec, params, pass_first_of_group, n);
  heads_scanned_ = true;
}

void DevicePreparation::record_compact(Recording& rec, std::size_t n) {
  if (!heads_scanned_) head_scan_.record(rec, n);
  Params params{{0, 0}, 1.0, 1.0, 1.0, 0, 0, 0, 0, 0, 0};
  dispatch_prepare(rec, params, pass_compact, n);
}

void DevicePreparation::record_hull(Recording& rec, std::size_t hull_count) {
  rec.fill(*predecessor_, 0xFFFFFFFFu);  // -1: not on the hull
  rec.barrier();
  Params params{{0, 0}, 1.0, 1.0, 1.0, 0, 0, 0, 0, 0, 0};
  dispatch_prepare(rec, params, pass_hull, hull_count);
  dispatch_prepare(rec, params, pass_predecessor, hull_count);
}

void DevicePreparation::record_sample(Recording& rec, std::size_t count, std::size_t stride) {
  Params params{{0, 0}, 1.0, 1.0, 1.0, 0, 0, 0, 0, std::int32_t(stride), 0};
  dispatch_prepare(rec, params, pass_sample, count);
}

}  // namespace expanse::detail::vk
