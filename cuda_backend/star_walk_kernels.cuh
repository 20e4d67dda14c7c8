#pragma once
// The star walks' kernels: a thread a site (first pass, or the only pass), a thread a listed site
// (the edge's walks, the handed-on sites, the second phase's searching sites), the second
// phase's sites whose inboxes hold their stars, and a warp a site (retry). Included by
// star_kernels.cu alone, which launches them (walk_stars).
#include <cstdint>

#include "star_common.cuh"
#include "star_scan.cuh"

namespace expanse::detail::cuda {
namespace {

/// Which pass of the star walks a site is in. Most sites finish within a small budget; the few
/// that run past it (hull-hugging and sparse-region sites whose searches span long rows of
/// cells) would hold their warps, and so their blocks' multiprocessor slots, long after the rest
/// are done (ncu, 1024^2 uniform, one pass: multiprocessors active 33% of the kernel's time).
/// So a first pass with a small budget lists them, and a second walks each again with a whole
/// warp (Walker::warp) and the full budget.
enum class WalkPass { only, first, retry };

/// Site i's walk, in the copy compiled for its grid's kind (GridKind): the branch is taken the
/// same way by every thread of a launch. H100, 4096^2 GPU-only, against one walk for every kind:
/// uniform 35.0 -> 34.6 ms, kuzmin 59.1 -> 55.2, gaussian 43.8 -> 42.7, 512^2 uniform 1.83 ->
/// 1.72. Integer lattices walk uniform cells, so their kernels branch on the boundaries alone
/// (with the three-way branch in front of the same two walks the 4096^2 lattice took 21.8 ms
/// instead of 20.7, ptxas placing its spill code a little apart).
template <Walker By, bool ExactLattice, bool FirstPass, bool ReadsInbox, bool Strips>
EXPANSE_DEVICE_FORCE StarWalk walk_star_of_kind(const GridView& g, const int* pred, int i, int* row, unsigned budget,
                                                const StarInbox& inbox) {
  const GridKind kind = ExactLattice ? (g.xb ? GridKind::any : GridKind::uniform) : kind_of(g);
  if (kind == GridKind::uniform)
    return walk_star_boxes<By, ExactLattice, FirstPass, ReadsInbox, Strips, GridKind::uniform>(g, pred, i, row, budget,
                                                                                                inbox);
  if (!ExactLattice && kind == GridKind::guided)
    return walk_star_boxes<By, ExactLattice, FirstPass, ReadsInbox, Strips, GridKind::guided>(g, pred, i, row, budget,
                                                                                               inbox);
  if (!ExactLattice && kind == GridKind::guided_tails)
    return walk_star_boxes<By, ExactLattice, FirstPass, ReadsInbox, Strips, GridKind::guided_tails>(g, pred, i, row,
                                                                                                     budget, inbox);
  return walk_star_boxes<By, ExactLattice, FirstPass, ReadsInbox, Strips>(g, pred, i, row, budget, inbox);
}

/// Walks site i's star and records it (info, owned; posts for the second phase). A site the
/// walk leaves goes to a list: `retry_list` (list_counts[0] long) takes a first pass's sites that
/// ran past its budget, for the warps; `handed_on_list` (list_counts[1]) a light first pass's
/// sites that met a candidate only the exact path decides, for a thread each (star_list_kernel).
/// The lists of the grid's edge (EdgeCells) are apart from the rest's: counters[7..8] count the
/// rest's, [10..11] the edge's.
template <Walker By = Walker::thread, bool ExactLattice = false, bool FirstPass = false, bool ReadsInbox = false,
          bool Strips = false>
__device__ __forceinline__ void walk_and_record(const GridView& g, const int* pred, int i, int* star,
                                                std::uint32_t* info, int* owned, unsigned int* counters,
                                                unsigned budget, WalkPass pass, int* retry_list,
                                                int* handed_on_list, unsigned int* list_counts,
                                                const StarInbox& inbox = {}) {
  int* row = star + static_cast<std::size_t>(i) * kStar;
  StarWalk w;
  if constexpr (By == Walker::warp)  // a retry: the full walk, no inbox
    w = walk_star_of_kind<By, ExactLattice, false, false, Strips>(g, pred, i, row, budget, {});
  else
    w = walk_star_of_kind<By, ExactLattice, FirstPass, ReadsInbox, Strips>(g, pred, i, row, budget, inbox);
  const unsigned predicates = w.predicates, cells = w.work;
  // One atomic per warp for the predicate count (first attempts of retried sites included);
  // the deferred count is rare. A warp walking one site holds its count spread over its lanes.
  const unsigned active = __activemask();
  const unsigned warp_total = __reduce_add_sync(active, predicates);
  const unsigned warp_max = __reduce_max_sync(active, cells);
  if ((threadIdx.x & 31) == __ffs(active) - 1) {
    atomicAdd(reinterpret_cast<unsigned long long*>(counters + 2), static_cast<unsigned long long>(warp_total));
    atomicMax(counters + 4, warp_max);
  }
  if constexpr (By == Walker::warp) {
    if ((threadIdx.x & 31) != 0) return;  // the rest is one site's, done once
  }
  // Counted on a site's last walk: the second pass's for a site the first pass hands on.
  const bool walked_again = pass == WalkPass::first && !w.ok && (cells > budget || w.handed_on);
  if (!walked_again && cells > 4096) atomicAdd(counters + 5, 1u);
  if (!w.ok) {
    info[i] = kDeferredBit;
    owned[i] = 0;
    if (walked_again) {
      if (handed_on_list && w.handed_on && cells <= budget)
        handed_on_list[atomicAdd(list_counts + 1, 1u)] = i;
      else
        retry_list[atomicAdd(list_counts, 1u)] = i;
      return;
    }
    if (cells > budget) atomicAdd(counters + 6, 1u);  // deferred by the budget
    atomicAdd(counters, 1u);
    return;
  }
  const std::uint32_t inf = star_info(w);
  info[i] = inf;
  owned[i] = owned_triangles(star, inf, i);
  if (inbox.posting()) post_star(inbox, star, inf, i, [](std::uint32_t* c) { return atomicAdd(c, 1u); });
}

/// The sites in the outer `depth` rings of the grid's cells (keys: each local site's cell, sorted).
/// Their walks are the longest by far: every site that runs past the first pass's budget on a
/// uniform input lies in the outermost ring (4M sites: 1,325 of them, the costliest 65,536
/// units, where the first pass allows 1,024), and on kuzmin those of the outermost take 45% of
/// the second pass's work, at most 65,536 units again against 24,170 one ring further in
/// (counted on the CPU). A warp walks such a site alone, and the last one to finish
/// set the second pass's length: ~9 ms of 48 at 4096^2 uniform (H100, ncu), the rest of the GPU
/// idle. So these sites take their first pass on a stream of their own (Context::edge_stream) of
/// the highest priority, alongside everyone else's first pass, and their second pass starts
/// early, at the main stream's priority (Context::low_stream), in the first phase's drain.
struct EdgeCells {
  const std::uint32_t* keys = nullptr;  ///< null: no edge set apart
  int gx = 0, gy = 0, depth = 0;

  EXPANSE_DEVICE_FORCE bool holds(int i) const {
    if (!keys) return false;
    const int key = static_cast<int>(keys[i]), y = key / gx, x = key - y * gx;
    return min(min(x, y), min(gx - 1 - x, gy - 1 - y)) < depth;
  }
};

/// list[0 .. *count) = the local sites that `edge` holds.
__global__ void edge_list_kernel(EdgeCells edge, int n, int* list, unsigned int* count) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i < n && edge.holds(i)) list[atomicAdd(count, 1u)] = i;
}

/// The first phase's walks (or the only phase's): thread t walks the t-th site of the phase,
/// local site t * phases, in cell order (faster than the sites' Morton order on the H100:
/// uniform 4096^2 230 against 244 ms, kuzmin 629 against 733, one phase). With two phases its
/// walks post to the odd sites' inboxes (StarInbox); the second phase's walks are
/// inbox_star_kernel's and star_list_kernel's.
template <int MinBlocks, bool ExactLattice = false, bool FirstPass = false>
__global__ void __launch_bounds__(128, MinBlocks) star_kernel(GridView g, const int* pred, int n, int* star,
                                                              std::uint32_t* info, int* owned,
                                                              unsigned int* counters, unsigned budget,
                                                              WalkPass pass, int* retry_list,
                                                              int* handed_on_list, EdgeCells edge,
                                                              int phases, StarInbox inbox,
                                                              bool ends_first = false) {
  const int b = ends_first ? ends_first_block(static_cast<int>(blockIdx.x), static_cast<int>(gridDim.x))
                           : static_cast<int>(blockIdx.x);
  const int i = (b * static_cast<int>(blockDim.x) + static_cast<int>(threadIdx.x)) * phases;
  if (i >= n) return;
  if (edge.holds(i)) return;  // the edge stream walks it
  walk_and_record<Walker::thread, ExactLattice, FirstPass>(g, pred, i, star, info, owned, counters, budget, pass,
                                                           retry_list, handed_on_list, counters + 7, inbox);
}

/// The sites list[0 .. *count), a thread each, as a first pass walks them: those that run past
/// `budget` go on to the warps (retry_list), and with the light walk (FirstPass) those that meet
/// an undecided candidate to handed_on_list; list_counts as walk_and_record's. Grid-stride, so
/// that a short list costs one small launch. Three uses:
///  - the light first pass's handed-on sites, walked in full (with the exact path) under the
///    first pass's budget. Nearly cocircular float inputs (decimal grids) send nearly every site
///    here: a warp each they took 115 ms at 1024^2 (H100);
///  - the first pass of the grid's edge (EdgeCells), on its own stream.
///  - the second phase's sites that need a search (inbox_star_kernel), reading their inboxes
///    (ReadsInbox), in the phase's pass.
template <int MinBlocks, bool ExactLattice = false, bool FirstPass = false, bool ReadsInbox = false,
          bool Strips = false>
__global__ void __launch_bounds__(128, MinBlocks) star_list_kernel(GridView g, const int* pred, int* star,
                                                                   std::uint32_t* info, int* owned,
                                                                   unsigned int* counters, unsigned budget,
                                                                   const int* list, const unsigned int* count,
                                                                   int* retry_list, int* handed_on_list,
                                                                   unsigned int* list_counts,
                                                                   WalkPass pass = WalkPass::first,
                                                                   StarInbox inbox = {}) {
  const unsigned sites = *count;
  for (unsigned k = blockIdx.x * blockDim.x + threadIdx.x; k < sites; k += gridDim.x * blockDim.x)
    walk_and_record<Walker::thread, ExactLattice, FirstPass, ReadsInbox, Strips>(
        g, pred, list[k], star, info, owned, counters, budget, pass, retry_list, handed_on_list, list_counts, inbox);
}

/// The second phase's first step (StarInbox): an odd site whose inbox holds its whole star
/// (walk_from_inbox) is recorded here, with no search; the others are listed in `search_list`
/// (*search_count long), in the phase's order within each block, for star_list_kernel. Counted on
/// the CPU (10^6 sites, quantile cells), 45% of the odd sites need no search, and in the phase's
/// kernel their lanes only waited for those that did: packed 32 searching sites to a warp, the
/// phase's lock-step work falls 25% (uniform), 30% (kuzmin), 35% (gaussian). One atomic a block
/// for the list's room.
constexpr int kInboxThreads = 256;
__global__ void __launch_bounds__(kInboxThreads) inbox_star_kernel(const int* pred, int n, int* star,
                                                                   std::uint32_t* info, int* owned, EdgeCells edge,
                                                                   StarInbox inbox, int* search_list,
                                                                   unsigned int* search_count, bool ends_first) {
  __shared__ unsigned int warp_base[kInboxThreads / 32];
  __shared__ unsigned int block_base;
  const int b = ends_first ? ends_first_block(static_cast<int>(blockIdx.x), static_cast<int>(gridDim.x))
                           : static_cast<int>(blockIdx.x);
  const int i = (b * kInboxThreads + static_cast<int>(threadIdx.x)) * 2 + 1;
  bool search = false;
  if (i < n && !edge.holds(i)) {
    // Walked twice where the inbox holds the star, the row written the second time only: half
    // the odd sites must search, and their rows are written again by the full walk. (Walked once,
    // writing the row as it went, this kernel took 1.76 ms instead of 1.15 at 4096^2 uniform,
    // H100.)
    StarWalk w;
    int mine = 0;
    if (walk_from_inbox(pred, i, nullptr, inbox, &w, &mine)) {
      walk_from_inbox(pred, i, star + static_cast<std::size_t>(i) * kStar, inbox, &w, &mine);
      info[i] = star_info(w);
      owned[i] = mine;
    } else {
      search = true;
    }
  }
  // The block's searching sites listed in thread order: neighbouring sites stay together for
  // the walks.
  const unsigned listed = __ballot_sync(0xffffffffu, search);
  const unsigned lane = threadIdx.x & 31, warp = threadIdx.x >> 5;
  if (lane == 0) warp_base[warp] = static_cast<unsigned>(__popc(listed));
  __syncthreads();
  if (threadIdx.x == 0) {
    unsigned total = 0;
    for (int k = 0; k < kInboxThreads / 32; ++k) {
      const unsigned count = warp_base[k];
      warp_base[k] = total;
      total += count;
    }
    block_base = total ? atomicAdd(search_count, total) : 0u;
  }
  __syncthreads();
  if (search) search_list[block_base + warp_base[warp] + __popc(listed & ((1u << lane) - 1u))] = i;
}

/// *to = *from, in stream order: a list's length at that point, kept while the list grows on.
__global__ void copy_count_kernel(const unsigned int* from, unsigned int* to) { *to = *from; }

/// The second pass: the sites a first pass listed (*count of them), with the full budget, each
/// walked by a whole warp. Measured on the H100 (2026-11-23, uniform 4096^2): packed 32 sites to
/// a warp the second pass ran 2.7x slower than a single pass (623 against 233 ms), their
/// divergent searches serialised; one site per warp on one thread still lost (285 against 228
/// ms), a heavy site's walk being a chain of dependent loads that one thread runs at ~1 us per
/// candidate.
///
/// `skip` (null: none): the list's first *skip sites are another launch's (the first phase's,
/// walked beside the second phase: launch_first_phase_retry).
template <int MinBlocks, bool ExactLattice = false, bool Strips = false>
__global__ void __launch_bounds__(128, MinBlocks) star_retry_kernel(GridView g, const int* pred, int* star,
                                                                    std::uint32_t* info, int* owned,
                                                                    unsigned int* counters, unsigned budget,
                                                                    const int* retry_list, const unsigned int* count,
                                                                    const unsigned int* skip = nullptr) {
  const unsigned sites = *count;
  const unsigned warps = gridDim.x * (blockDim.x / 32);
  for (unsigned k = (skip ? *skip : 0u) + (blockIdx.x * blockDim.x + threadIdx.x) / 32; k < sites; k += warps)
    walk_and_record<Walker::warp, ExactLattice, false, false, Strips>(
        g, pred, retry_list[k], star, info, owned, counters, budget, WalkPass::retry, nullptr, nullptr, nullptr);
}

}  // namespace
}  // namespace expanse::detail::cuda
