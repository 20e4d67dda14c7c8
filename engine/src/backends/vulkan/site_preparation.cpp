// Vulkan structs are value-initialised from their sType alone ({VK_STRUCTURE_TYPE_...}).
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#include "backends/vulkan/site_preparation.hpp"

#include <cmath>
#include <cstring>
#include <ranges>

#include "backends/vulkan/device_preparation.hpp"
#include "backends/vulkan/host_threads.hpp"
#include "backends/vulkan/kept_buffers.hpp"
#include "expanse/error.hpp"
#include "host_device.h"
#include "input/morton.hpp"
#include "input/parallel.hpp"
#include "support/timing.hpp"

namespace expanse::detail::vk {

using namespace shared;

void SiteCopy::start() {
  if (rec || pieces.empty()) return;
  rec.emplace(ctx, /*timed=*/false);
  rec->barrier_after_compute();
  VkDeviceSize at = 0;
  for (const Piece& piece : pieces) {
    rec->copy(*piece.from, *staging, piece.bytes, 0, at);
    at += piece.bytes;
  }
  rec->barrier_to_host();
  rec->submit_only();
  host = std::async(std::launch::async, [this] {
    rec->wait();
    const auto begin = Clock::now();
    // Threads of its own: the host's shared pool runs one job at a time, and meanwhile it
    // readies the output vectors (a second job runs on its caller alone: 75-93 ms for these
    // 320 MB at 4096^2 on the H100's host, 2026-11-25).
    const char* from = static_cast<const char*>(staging->mapped());
    for (const Piece& piece : pieces) {
      vk::parallel_chunks(std::size_t(piece.bytes), host_workers(std::size_t(piece.bytes) >> 6),
                          [&](std::size_t first, std::size_t last, unsigned) {
                            std::memcpy(static_cast<char*>(piece.to) + first, from + first, last - first);
                          });
      from += piece.bytes;
    }
    host_ms = ms_since(begin);
  });
}

namespace {

// How the points are scaled: as prepare_sites scales them on the host.
PreparationScale preparation_scale(const InputScan& scan) {
  const Quantiser quantiser(scan.bounds);
  PreparationScale scale;
  scale.origin[0] = quantiser.origin_x;
  scale.origin[1] = quantiser.origin_y;
  scale.scale = quantiser.scale;
  if (scan.scale_exponent <= 1023) {
    scale.factor = scan.factor;
  } else {  // past 2^1023 (subnormal input): two exact steps, as ldexp's one
    scale.factor = 0x1p1000;
    scale.second_factor = std::ldexp(1.0, scan.scale_exponent - 1000);
  }
  return scale;
}

// The preparation's buffers, kept by the context: the sites and the hull predecessors land in
// the star grid's input buffers (host-visible where a CPU device works in place).
PreparationBuffers preparation_buffers(Context& ctx, const DevicePreparation& prep, std::size_t n, bool in_place) {
  Buffer& counters = kept(ctx, k_prep_counters, 64, false);
  return PreparationBuffers{&kept(ctx, k_prep_raw, bytes_of(n, 16), false),
                             {&kept(ctx, k_prep_keys0, bytes_of(n, 8), false), &kept(ctx, k_prep_keys1, bytes_of(n, 8), false)},
                             {&kept(ctx, k_prep_values0, bytes_of(n, 4), false), &kept(ctx, k_prep_values1, bytes_of(n, 4), false)},
                             &kept(ctx, k_prep_sorted, bytes_of(n, 16), false),
                             &kept(ctx, k_prep_first, bytes_of(n, 4), false),
                             &kept(ctx, k_prep_heads, bytes_of(n, 4), false),
                             &kept(ctx, k_prep_head_sums, prep.head_sums_bytes(n), false),
                             &kept(ctx, k_prep_counts, prep.counts_bytes(n), false),
                             &kept(ctx, k_prep_count_sums, prep.count_sums_bytes(n), false),
                             &kept(ctx, k_input_sites, bytes_of(n, 16), in_place),
                             &kept(ctx, k_prep_site_input, bytes_of(n, 4), false),
                             &kept(ctx, k_prep_rank, bytes_of(n, 4), false),
                             &kept(ctx, k_prep_representative, bytes_of(n, 4), false),
                             &counters,  // the hull's buffers, bound once it is known
                             &counters,
                             &kept(ctx, k_input_predecessor, bytes_of(n, 4), in_place),
                             &counters};
}

// Submits what `record` records, then the counters' copy to `words`, and reads them into `word`.
template <class Record>
void submit_and_read(Context& ctx, Buffer& counters, Buffer& words, std::vector<StageTime>& device,
                     std::uint32_t (&word)[COUNTER_WORDS], Record&& record) {
  Recording rec(ctx);
  rec.barrier();  // after the ring's copies
  record(rec);
  rec.copy(counters, words, 64);
  rec.barrier_to_host();
  for (StageTime& stage : rec.submit()) device.push_back(std::move(stage));
  std::memcpy(word, words.mapped(), sizeof(word));
}

// The sort by Morton code and the merge of equal points; returns the number of sites.
std::size_t sort_and_merge(Context& ctx, DevicePreparation& prep, Buffer& counters, Buffer& words,
                           std::size_t n, const PreparationScale& scale, InputGrowResult& result) {
  auto& device = result.grown.device_stages;
  std::uint32_t word[COUNTER_WORDS];
  const auto submit = [&](auto&& record) { submit_and_read(ctx, counters, words, device, word, record); };
  submit([&](Recording& rec) {
    prep.record_sort(rec, n, scale);
    rec.timestamp("vulkan: prepare (sort)");
    prep.record_compact(rec, n);
    rec.timestamp("vulkan: prepare (merge)");
  });
  if (word[PREPARE_COUNTER_LONG_RUN] != 0) {
    // A run of equal codes too long to search pairwise (many copies of a point, or a cluster
    // finer than the quantisation): sorted again by (code, x, y), equal points side by side.
    submit([&](Recording& rec) {
      prep.record_sort_by_point(rec, n);
      rec.timestamp("vulkan: prepare (sort by point)");
      prep.record_compact(rec, n);
      rec.timestamp("vulkan: prepare (merge)");
    });
  }
  const std::size_t m = word[PREPARE_COUNTER_SITES];
  if (m < 1 || m > n) throw Error(ErrorCode::internal, "Vulkan: the device's preparation counted " + std::to_string(m) + " sites");
  return m;
}

}  // namespace

bool prepare_on_device(Context& ctx, const Tuning& tuning, const InputGrowInput& input,
                       InputGrowResult& result, SiteCopy& copy) {
  const std::size_t n = input.points.size();
  if (n >= (std::size_t{1} << 30) || bytes_of(n, 16) > ctx.max_buffer_bytes()) return false;
  const InputScan& scan = input.scan;
  const PreparationScale scale = preparation_scale(scan);
  // Every point its own representative, written on another host thread while the device
  // works (the usual case; the device's map replaces it where points repeat).
  SiteSet& sites = result.sites;
  auto identity = std::async(std::launch::async, [&sites, n] {
    auto& representative = sites.representative;
    representative.reserve(n);
    advise_huge_pages(representative.data(), n * sizeof(std::int32_t));
    const auto ids = std::views::iota(std::int32_t{0}, std::int32_t(n));
    representative.assign(ids.begin(), ids.end());
  });
  auto& host = result.grown.host_stages;
  auto& device = result.grown.device_stages;
  DevicePreparation prep(ctx, workgroup(ctx, 64));
  Buffer& counters = kept(ctx, k_prep_counters, 64, false);
  Buffer& words = kept(ctx, k_words, 64, true);
  PreparationBuffers buffers = preparation_buffers(ctx, prep, n, works_in_place(ctx, tuning));
  prep.bind(buffers);

  Stopwatch watch;
  const StagingRing::Upload raw[] = {{input.points.data(), buffers.raw->handle(), 0, bytes_of(n, 16)}};
  ctx.staging().upload(raw);
  host.push_back({"vulkan: upload of the input", watch.ms()});

  watch.restart();
  const std::size_t m = sort_and_merge(ctx, prep, counters, words, n, scale, result);
  host.push_back({"vulkan: prepare on the device (submit + wait)", watch.ms()});

  std::uint32_t word[COUNTER_WORDS];
  const auto submit = [&](auto&& record) { submit_and_read(ctx, counters, words, device, word, record); };
  auto start = Clock::now();
  const std::vector<std::int32_t>* hull_input = input.hull();
  host.push_back({"vulkan: wait for the host's hull", ms_since(start)});
  if (!hull_input) return false;  // collinear: the host's path handles it
  start = Clock::now();
  const std::size_t h = hull_input->size();
  buffers.hull_input = &kept(ctx, k_prep_hull_input, bytes_of(h, 4), false);
  buffers.hull_sites = &kept(ctx, k_prep_hull_sites, bytes_of(h, 4), false);
  prep.bind(buffers);
  const StagingRing::Upload hull_upload[] = {{hull_input->data(), buffers.hull_input->handle(), 0, bytes_of(h, 4)}};
  ctx.staging().upload(hull_upload);
  // The grid's sample of the sites (star_cells.hpp) into the sorted points' buffer, free now.
  const std::size_t stride = star_cell_sample_stride(m), samples = m / stride;
  submit([&](Recording& rec) {
    prep.record_hull(rec, h);
    prep.record_sample(rec, samples, stride);
    rec.timestamp("vulkan: prepare (hull, sample)");
  });

  // What the host needs before the growth: the hull and the sample. The sites, their input
  // indices and the representatives follow while the stars grow (SiteCopy).
  sites.scale_exponent = scan.scale_exponent;
  sites.integer_coordinates = scan.integer_coordinates;
  sites.bounds = scan.bounds;
  resize_for_parallel_write(sites.points, m);
  resize_for_parallel_write(sites.input_index, m);
  Hull& hull = result.hull;
  hull.sites.resize(h);
  copy.sample_points.resize(samples);
  const StagingRing::Download pieces[] = {
      {buffers.hull_sites->handle(), 0, hull.sites.data(), bytes_of(h, 4)},
      {buffers.sorted->handle(), 0, copy.sample_points.data(), bytes_of(samples, 16)}};
  ctx.staging().download(pieces);
  identity.get();
  copy.staging = &kept(ctx, k_sites_to_host, bytes_of(m, 20) + (m < n ? bytes_of(n, 4) : 0), true);
  copy.pieces = {{buffers.site_points, sites.points.data(), bytes_of(m, 16)},
                 {buffers.site_input, sites.input_index.data(), bytes_of(m, 4)}};
  if (m < n) copy.pieces.push_back({buffers.representative, sites.representative.data(), bytes_of(n, 4)});
  resize_for_parallel_write(hull.predecessor, m);
  detail::parallel_chunks(m, [&](std::size_t, std::size_t begin, std::size_t end) {
    std::fill(hull.predecessor.begin() + std::ptrdiff_t(begin), hull.predecessor.begin() + std::ptrdiff_t(end), -1);
  });
  for (std::size_t k = 0; k < h; ++k) {
    const std::int32_t site = hull.sites[k];
    if (site < 0 || std::size_t(site) >= m) throw Error(ErrorCode::internal, "Vulkan: the device mapped a hull site out of range");
    hull.predecessor[std::size_t(site)] = hull.sites[(k + h - 1) % h];
  }
  host.push_back({"vulkan: hull and the grid's sample to the host", ms_since(start)});
  return true;
}

}  // namespace expanse::detail::vk
