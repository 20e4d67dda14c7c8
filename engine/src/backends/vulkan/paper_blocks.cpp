// Vulkan structs are value-initialised from their sType alone ({VK_STRUCTURE_TYPE_...}).
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#include "backends/vulkan/paper_blocks.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "backends/vulkan/dispatch.hpp"
#include "backends/vulkan/host_bucketing.hpp"
#include "backends/vulkan/host_threads.hpp"
#include "backends/vulkan/shader_registry.hpp"
#include "expanse/error.hpp"
#include "host_device.h"
#include "support/timing.hpp"

namespace expanse::detail::vk {
namespace {

using namespace shared;

struct Sorted : GridFrame {
  std::vector<Point2> points;            // sites sorted by cell (row-major)
  std::vector<std::int32_t> to_site;     // sorted id -> SiteSet id
  std::vector<std::int32_t> predecessor; // in sorted ids
  std::vector<std::int32_t> cell_start;  // cells^2 + 1
  std::vector<std::int32_t> cell_of;     // sorted id -> cell
};

Sorted bucket(const GrowInput& input, int cells) {
  const SiteSet& sites = input.sites;
  const std::size_t n = std::size_t(sites.size());
  Sorted s;
  static_cast<GridFrame&>(s) = GridFrame(sites, cells);
  std::vector<std::int32_t> cell(n);
  s.cell_start.assign(std::size_t(cells) * std::size_t(cells) + 1, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const Point2& p = sites.points[i];
    const int cx = cell_coord(p.x, s.origin[0], s.inv_width[0], cells);
    const int cy = cell_coord(p.y, s.origin[1], s.inv_width[1], cells);
    cell[i] = cy * cells + cx;
    ++s.cell_start[std::size_t(cell[i]) + 1];
  }
  for (std::size_t c = 1; c < s.cell_start.size(); ++c) s.cell_start[c] += s.cell_start[c - 1];
  std::vector<std::int32_t> fill(s.cell_start.begin(), s.cell_start.end() - 1);
  std::vector<std::int32_t> to_sorted(n);
  s.to_site.resize(n);
  s.points.resize(n);
  s.cell_of.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::int32_t at = fill[std::size_t(cell[i])]++;
    to_sorted[i] = at;
    s.to_site[std::size_t(at)] = std::int32_t(i);
    s.points[std::size_t(at)] = sites.points[i];
    s.cell_of[std::size_t(at)] = cell[i];
  }
  s.predecessor.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    const std::int32_t p = input.hull.predecessor[std::size_t(s.to_site[k])];
    s.predecessor[k] = p < 0 ? -1 : to_sorted[std::size_t(p)];
  }
  return s;
}

void finish(const Sorted& s, const std::vector<std::int32_t>& raw, std::size_t count,
            GrowResult& result) {
  auto& triangles = result.partial.triangles;
  triangles.resize(count);
  const std::size_t n = s.to_site.size();
  for (std::size_t t = 0; t < count; ++t)
    for (int k = 0; k < 3; ++k) {
      const std::int32_t id = raw[3 * t + std::size_t(k)];
      if (id < 0 || std::size_t(id) >= n)
        throw Error(ErrorCode::internal, "Vulkan: the device returned site id " +
                                             std::to_string(id) + " of " + std::to_string(n));
      triangles[t][std::size_t(k)] = s.to_site[std::size_t(id)];
    }
}

// The blocks' lists: each site's owner block, each block's BLOCK_INFO_WORDS words, the
// block-local site ids and cell starts (a block's cells with its halo), and the sizes of the
// blocks' edge sets and active lists.
struct BlockLists {
  std::vector<std::int32_t> owner, info, local_ids, local_cells;
  std::size_t hash_total = 0, active_total = 0;
};

BlockLists block_lists(const Sorted& s, int B, int K, int halo) {
  const int cells = s.cells;
  const std::size_t n = s.points.size();
  const int blocks = B * B;
  BlockLists lists;
  auto& [owner, info, local_ids, local_cells, hash_total, active_total] = lists;
  // Owner block of each site, local lists (ext cell range, local cell order).
  owner.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    const int cx = s.cell_of[k] % cells, cy = s.cell_of[k] / cells;
    owner[k] = (cy / K) * B + (cx / K);
  }
  info.resize(std::size_t(blocks) * BLOCK_INFO_WORDS);
  for (int bj = 0; bj < B; ++bj) {
    for (int bi = 0; bi < B; ++bi) {
      const int b = bj * B + bi;
      const int lox = std::max(0, bi * K - halo), hix = std::min(cells - 1, bi * K + K - 1 + halo);
      const int loy = std::max(0, bj * K - halo), hiy = std::min(cells - 1, bj * K + K - 1 + halo);
      std::int32_t* in = &info[std::size_t(b) * BLOCK_INFO_WORDS];
      in[BLOCK_LO_X] = lox;
      in[BLOCK_LO_Y] = loy;
      in[BLOCK_HI_X] = hix;
      in[BLOCK_HI_Y] = hiy;
      in[BLOCK_CELL_BASE] = std::int32_t(local_cells.size());
      const std::size_t slot_base = local_ids.size();
      in[BLOCK_SLOT_BASE] = std::int32_t(slot_base);
      // Seed: own site nearest the block centre (any choice is correct; this one is the paper's).
      const double cx = s.origin[0] + (bi * K + K * 0.5) / s.inv_width[0];
      const double cy = s.origin[1] + (bj * K + K * 0.5) / s.inv_width[1];
      double best = INFINITY;
      int seed = -1;
      for (int y = loy; y <= hiy; ++y) {
        for (int x = lox; x <= hix; ++x) {
          local_cells.push_back(std::int32_t(local_ids.size()));
          const int c = y * cells + x;
          for (int k = s.cell_start[std::size_t(c)]; k < s.cell_start[std::size_t(c) + 1]; ++k) {
            if (owner[std::size_t(k)] == b) {
              const double dx = s.points[std::size_t(k)].x - cx, dy = s.points[std::size_t(k)].y - cy;
              if (dx * dx + dy * dy < best) {
                best = dx * dx + dy * dy;
                seed = int(local_ids.size() - slot_base);
              }
            }
            local_ids.push_back(k);
          }
        }
      }
      local_cells.push_back(std::int32_t(local_ids.size()));
      const std::size_t count = local_ids.size() - slot_base;
      if (count > 65535)
        throw Error(ErrorCode::too_large,
                    "paper layout: a block holds " + std::to_string(count) +
                        " sites with its halo (at most 65535); use more blocks");
      if (local_ids.size() > std::size_t(INT32_MAX) / 2)
        throw Error(ErrorCode::too_large, "paper layout: too many block-local sites");
      in[BLOCK_SITE_COUNT] = std::int32_t(count);
      in[BLOCK_SEED_SLOT] = count >= 2 ? seed : -1;
      const std::size_t hash_cap = 8 * count + 64, active_cap = 3 * count + 64;
      in[BLOCK_HASH_BASE] = std::int32_t(hash_total);
      in[BLOCK_HASH_CAPACITY] = std::int32_t(hash_cap);
      in[BLOCK_ACTIVE_BASE] = std::int32_t(active_total);
      in[BLOCK_ACTIVE_CAPACITY] = std::int32_t(active_cap);
      hash_total += hash_cap;
      active_total += 2 * active_cap;
    }
  }
  return lists;
}

}  // namespace

void grow_blocks(Context& ctx, const Tuning& tuning, const GrowInput& input, GrowResult& result) {
  const Layout& layout = input.layout;
  const std::size_t n = std::size_t(input.sites.size());
  if (layout.blocks_per_side < 1 || layout.buckets_per_block_side < 1 ||
      layout.blocks_per_side > 4096 || layout.buckets_per_block_side > 4096 ||
      !(layout.halo_fraction >= 0.0 && layout.halo_fraction <= 1.0) ||
      layout.threads_per_block < 0)
    throw Error(ErrorCode::invalid_argument,
                "paper layout: blocks and buckets per side must be in [1, 4096], halo in [0, 1]");
  const int B = layout.blocks_per_side, K = layout.buckets_per_block_side;
  const long long cells_ll = (long long)B * K;
  if (cells_ll > 16384)
    throw Error(ErrorCode::invalid_argument, "paper layout: blocks x buckets per side > 16384");
  const int cells = int(cells_ll);
  const int halo = int(std::ceil(layout.halo_fraction * K));

  auto start = Clock::now();
  const Sorted s = bucket(input, cells);
  const int blocks = B * B;
  const BlockLists lists = block_lists(s, B, K, halo);
  const auto& [owner, info, local_ids, local_cells, hash_total, active_total] = lists;
  result.host_stages.push_back({"vulkan: bucket + blocks", ms_since(start)});

  const std::size_t capacity = 2 * n;
  ctx.require_fits(bytes_of(n, 16), "the sites");
  ctx.require_fits(bytes_of(local_ids.size(), 4), "the block-local site lists");
  ctx.require_fits(bytes_of(hash_total, 4), "the blocks' edge sets");
  ctx.require_fits(bytes_of(active_total, 4), "the blocks' active edge lists");
  ctx.require_fits(bytes_of(capacity, 12), "the triangle output");

  start = Clock::now();
  Buffer sites(ctx, bytes_of(n, 16), false);
  Buffer ids(ctx, bytes_of(local_ids.size(), 4), false);
  Buffer cell_start(ctx, bytes_of(local_cells.size(), 4), false);
  Buffer predecessor(ctx, bytes_of(n, 4), false);
  Buffer owners(ctx, bytes_of(n, 4), false);
  Buffer block_info(ctx, bytes_of(info.size(), 4), false);
  Buffer edge_set(ctx, bytes_of(hash_total, 4), false);
  Buffer active(ctx, bytes_of(active_total, 4), false);
  Buffer triangles(ctx, bytes_of(capacity, 12), false);
  Buffer counters(ctx, 64, false);
  Buffer words(ctx, 64, true);
  // Through the context's staging ring, chunk by chunk (the kernel's recording starts with a
  // barrier after these copies).
  const StagingRing::Upload pieces[] = {
      {s.points.data(), sites.handle(), 0, bytes_of(n, 16)},
      {local_ids.data(), ids.handle(), 0, bytes_of(local_ids.size(), 4)},
      {local_cells.data(), cell_start.handle(), 0, bytes_of(local_cells.size(), 4)},
      {s.predecessor.data(), predecessor.handle(), 0, bytes_of(n, 4)},
      {owner.data(), owners.handle(), 0, bytes_of(n, 4)},
      {info.data(), block_info.handle(), 0, bytes_of(info.size(), 4)}};
  ctx.staging().upload(pieces);
  // The buffers above outlive no copy in flight, even when this call throws.
  struct Idle {
    Context& ctx;
    ~Idle() {
      try {
        ctx.wait_staging();
      } catch (...) {
      }
    }
  } idle{ctx};
  result.host_stages.push_back({"vulkan: allocate + stage", ms_since(start)});

  std::uint32_t threads = std::uint32_t(layout.threads_per_block);
  if (threads == 0)
    threads = std::uint32_t(std::clamp(std::sqrt(double(n) / blocks), 32.0, 1024.0));
  threads = workgroup(ctx, threads);
  const std::uint32_t spec[] = {threads, loop_budget(ctx, tuning, false)};
  Kernel& kernel = ctx.kernel("blocks", spirv::blocks(), 10, sizeof(BlockParams), spec);
  Buffer* bindings[] = {&sites, &ids, &cell_start, &predecessor, &owners,
                        &block_info, &edge_set, &active, &triangles, &counters};
  kernel.bind(bindings);

  start = Clock::now();
  Recording rec(ctx);
  rec.barrier();  // after the ring's copies
  rec.fill(edge_set, 0xffffffffu);
  rec.fill(counters, 0);
  rec.barrier();
  rec.timestamp("vulkan: upload");
  BlockParams params{{s.origin[0], s.origin[1]}, {s.inv_width[0], s.inv_width[1]}, cells, blocks, 0, int(capacity)};
  dispatch_over(ctx, rec, kernel, params, params.first_block, std::uint64_t(blocks), 1);  // a workgroup a block
  rec.barrier();
  rec.timestamp("vulkan: blocks");
  rec.copy(counters, words, counters.size());
  rec.barrier_to_host();
  result.device_stages = rec.submit();
  result.host_stages.push_back({"vulkan: submit + wait", ms_since(start)});

  start = Clock::now();
  std::uint32_t count[COUNTER_WORDS];
  std::memcpy(count, words.mapped(), sizeof(count));
  if (count[COUNTER_OVERFLOW] != 0 || count[COUNTER_TRIANGLES] > capacity)
    throw Error(ErrorCode::internal, "Vulkan: block output overflowed its capacity");
  std::vector<std::int32_t> raw(std::size_t(count[COUNTER_TRIANGLES]) * 3);
  const StagingRing::Download made[] = {{triangles.handle(), 0, raw.data(), bytes_of(raw.size(), 4)}};
  ctx.staging().download(made);
  reserve_full_triangulation(result.partial, n, input.hull.sites.size());
  finish(s, raw, count[COUNTER_TRIANGLES], result);
  result.partial.deferred_expansions = count[COUNTER_DEFERRED];
  result.iterations = count[COUNTER_BLOCK_ITERATIONS];
  result.host_stages.push_back({"vulkan: read back", ms_since(start)});
}

}  // namespace expanse::detail::vk
