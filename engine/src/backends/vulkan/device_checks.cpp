// The Vulkan backend's passes run on their own, for the start-up self-test and the tests
// (vulkan_backend.hpp).
// Vulkan structs are value-initialised from their sType alone ({VK_STRUCTURE_TYPE_...}).
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#include <cstring>
#include <mutex>

#include "backends/vulkan/device_bucketing.hpp"
#include "backends/vulkan/host_bucketing.hpp"
#include "backends/vulkan/host_threads.hpp"
#include "backends/vulkan/shader_registry.hpp"
#include "backends/vulkan/vulkan_backend.hpp"
#include "host_device.h"

namespace expanse::detail::vk {

using namespace shared;

void run_predicate_kernel(Context& ctx, std::span<const double> cases,
                          std::vector<std::int32_t>& signs, std::vector<double>& eft) {
  std::lock_guard lock(ctx.mutex());
  const std::size_t count = cases.size() / 8;
  signs.assign(count * PREDICATE_TEST_SIGNS, 0);
  eft.assign(count * PREDICATE_TEST_EFT, 0.0);
  if (count == 0) return;
  Buffer in(ctx, cases.size_bytes(), false);
  Buffer out_signs(ctx, bytes_of(count * PREDICATE_TEST_SIGNS, 4), false);
  Buffer out_eft(ctx, bytes_of(count * PREDICATE_TEST_EFT, 8), false);
  Buffer upload(ctx, cases.size_bytes(), true);
  Buffer download(ctx, out_signs.size() + out_eft.size(), true);
  std::memcpy(upload.mapped(), cases.data(), cases.size_bytes());
  const std::uint32_t wg = 64;
  const std::uint32_t spec[] = {wg};
  Kernel& kernel = ctx.kernel("predicate_test", spirv::predicate_test(), 3, sizeof(PredicateTestParams), spec);
  Buffer* bindings[] = {&in, &out_signs, &out_eft};
  kernel.bind(bindings);
  Recording rec(ctx);
  rec.copy(upload, in, cases.size_bytes());
  rec.barrier();
  PredicateTestParams params{int(count), 0, 0, 0};
  rec.dispatch(kernel, &params, std::uint32_t((count + wg - 1) / wg));
  rec.barrier();
  rec.copy(out_signs, download, out_signs.size(), 0, 0);
  rec.copy(out_eft, download, out_eft.size(), 0, out_signs.size());
  rec.barrier();
  rec.submit();
  std::memcpy(signs.data(), download.mapped(), signs.size() * 4);
  std::memcpy(eft.data(), static_cast<char*>(download.mapped()) + out_signs.size(),
              eft.size() * 8);
}

DeviceBuckets bucket_on_device(Context& ctx, const SiteSet& sites, const Hull& hull, int cells) {
  std::lock_guard lock(ctx.mutex());
  const std::size_t n = std::size_t(sites.size());
  const std::size_t cell_entries = std::size_t(cells) * std::size_t(cells) + 1;
  const std::uint32_t wg = 64;
  DeviceBucketing bucketing(ctx, wg, /*quantile_cells=*/false);
  Buffer input_sites(ctx, bytes_of(n, 16), false), input_predecessor(ctx, bytes_of(n, 4), false);
  Buffer cell_key(ctx, bytes_of(n, 4), false), cell_start(ctx, bytes_of(cell_entries, 4), false);
  Buffer cursor(ctx, bytes_of(cell_entries, 4), false), unordered(ctx, bytes_of(n, 4), false);
  Buffer sorted(ctx, bytes_of(n, 16), false), to_site(ctx, bytes_of(n, 4), false);
  Buffer to_sorted(ctx, bytes_of(n, 4), false), predecessor(ctx, bytes_of(n, 4), false);
  Buffer triangles(ctx, 16, false), counters(ctx, 64, false);
  Buffer scan_sums(ctx, bucketing.scan_sums_bytes(cell_entries), false), no_bounds(ctx, 16, false);
  bucketing.bind({&input_sites, &input_predecessor, &cell_key, &cell_start, &cursor, &unordered,
                  &sorted, &to_site, &to_sorted, &predecessor, &triangles, &counters, &scan_sums, &no_bounds});
  Buffer upload(ctx, bytes_of(n, 20), true);
  std::memcpy(upload.mapped(), sites.points.data(), bytes_of(n, 16));
  std::memcpy(static_cast<char*>(upload.mapped()) + bytes_of(n, 16), hull.predecessor.data(), bytes_of(n, 4));
  // Download layout: sorted sites, cell starts, to_site, predecessor, counters.
  const VkDeviceSize o_cells = bytes_of(n, 16), o_to_site = o_cells + bytes_of(cell_entries, 4),
                     o_pred = o_to_site + bytes_of(n, 4), o_counters = o_pred + bytes_of(n, 4);
  Buffer download(ctx, o_counters + 64, true);
  Recording rec(ctx);
  rec.copy(upload, input_sites, bytes_of(n, 16), 0);
  rec.copy(upload, input_predecessor, bytes_of(n, 4), bytes_of(n, 16));
  rec.barrier();
  const GridFrame frame(sites, cells);
  bucketing.record_sort(rec, {{frame.origin[0], frame.origin[1]}, {frame.inv_width[0], frame.inv_width[1]}, cells}, n);
  rec.copy(sorted, download, bytes_of(n, 16), 0, 0);
  rec.copy(cell_start, download, bytes_of(cell_entries, 4), 0, o_cells);
  rec.copy(to_site, download, bytes_of(n, 4), 0, o_to_site);
  rec.copy(predecessor, download, bytes_of(n, 4), 0, o_pred);
  rec.copy(counters, download, 64, 0, o_counters);
  rec.barrier();
  rec.submit();
  const char* out = static_cast<const char*>(download.mapped());
  DeviceBuckets b;
  b.sites.assign(reinterpret_cast<const Point2*>(out), reinterpret_cast<const Point2*>(out) + n);
  auto ints = [&](VkDeviceSize offset, std::size_t count) {
    const auto* p = reinterpret_cast<const std::int32_t*>(out + offset);
    return std::vector<std::int32_t>(p, p + count);
  };
  b.cell_start = ints(o_cells, cell_entries);
  b.to_site = ints(o_to_site, n);
  b.predecessor = ints(o_pred, n);
  b.crowded = reinterpret_cast<const std::uint32_t*>(out + o_counters)[COUNTER_CROWDED_CELL] != 0;
  return b;
}

std::string eft_self_test(Context& ctx) {
  // a.x * a.y with a.x = a.y = 1 + 2^-30: exact 1 + 2^-29 + 2^-60; rounds to 1 + 2^-29, so
  // two_product's error must be exactly 2^-60, and a.x * a.y + b.x with b.x = -(1 + 2^-29) must
  // give 0 (an fma would give 2^-60). two_sum(1, 2^-60) must report error 2^-60.
  const double u = 1.0 + 0x1p-30;
  std::vector<double> cases = {u, u, -(1.0 + 0x1p-29), 0, 0, 1, 1, 1,
                               1.0, 0x1p-60, 0, 0, 0, 1, 1, 1};
  std::vector<std::int32_t> signs;
  std::vector<double> eft;
  run_predicate_kernel(ctx, cases, signs, eft);
  if (eft[1] != 1.0 + 0x1p-29 || eft[2] != 0x1p-60) return "two_product is not error-free";
  if (eft[3] != 0.0) return "a*b+c was fused into an fma despite `precise`";
  if (eft[4] != 0x1p-60) return "two_sum is not error-free";
  return {};
}


}  // namespace expanse::detail::vk
