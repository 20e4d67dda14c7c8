// Per-site star layout: every site grows its own star independently (docs/algorithm.md).
//
//   upload -> bucket (cell keys, radix sort, gather, cell starts, hull predecessors)
//          -> stars (nearest neighbour, CCW walk, CW walk; count owned triangles)
//          -> scan (triangle offsets)  [one 8-byte read-back: output size + deferred count]
//          -> emit (triangles in site ids + neighbours from the stars) -> download
//
// Work runs in sorted-by-cell order ("local ids"): neighbouring threads walk neighbouring
// cells, so their point reads share cache lines. A triangle is owned by its smallest local id;
// any total order works, each triangle is still emitted exactly once.
#include <cub/block/block_scan.cuh>
#include <cub/device/device_radix_sort.cuh>
#include <cub/device/device_segmented_radix_sort.cuh>
#include <cub/device/device_scan.cuh>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <future>
#include <memory>
#include <optional>
#include <type_traits>

#include "cuda_internal.hpp"
#include "support/timing.hpp"
#include "input/parallel.hpp"
#include "bucket_kernels.cuh"
#include "star_grid.hpp"
#include "star_scan.cuh"
#include "star_view.cuh"

namespace expanse::detail::cuda {
namespace {

/// Which pass of the star walks a site is in. Most sites finish within a small budget; the few
/// that run past it (hull-hugging and sparse-region sites whose searches span long rows of
/// cells) would hold their warps, and so their blocks' multiprocessor slots, long after the rest
/// are done (ncu, 1024^2 uniform, one pass: multiprocessors active 33% of the kernel's time).
/// So a first pass with a small budget lists them, and a second walks each again with a whole
/// warp (Walker::warp) and the full budget.
enum class WalkPass { only, first, retry };

/// `retry_list` (list_counts[0] long) takes a first pass's sites that ran past its budget, for
/// the warps; `undecided_list` (list_counts[1]) a light first pass's sites that met a candidate
/// only the exact path decides, for a thread each (star_list_kernel). The lists of the grid's
/// edge (EdgeCells) are apart from the rest's: counters[7..8] count the rest's, [10..11] the edge's.
template <StarSearch Search, Walker By = Walker::thread, bool ExactLattice = false, bool FirstPass = false,
          bool ReadsInbox = false, bool Strips = false>
__device__ __forceinline__ void walk_and_record(const GridView& g, const int* pred, int i, int* star,
                                                std::uint32_t* info, int* owned, unsigned int* counters,
                                                unsigned budget, WalkPass pass, int* retry_list,
                                                int* undecided_list, unsigned int* list_counts,
                                                const StarInbox& inbox = {}) {
  int* row = star + static_cast<std::size_t>(i) * kStar;
  StarWalk w;
  // A walk of its own for each kind of grid (GridKind), the branch taken the same way by every
  // thread of a launch: H100, 4096^2 GPU-only, uniform 35.0 -> 34.6 ms, kuzmin 59.1 -> 55.2,
  // gaussian 43.8 -> 42.7, 512^2 uniform 1.83 -> 1.72 (session 27 call 4). Integer lattices walk
  // uniform cells, so their kernels branch on the boundaries alone, as they did with the uniform
  // copy alone: with the three-way branch in front of the same two walks the 4096^2 lattice took
  // 21.8 ms (call 4), with this one 20.7 (call 8), ptxas placing its spill code a little apart.
  const GridKind kind = ExactLattice ? (g.xb ? GridKind::any : GridKind::uniform) : kind_of(g);
  if constexpr (By == Walker::warp) {
    if (kind == GridKind::uniform)
      w = walk_star_boxes<Walker::warp, ExactLattice, false, false, Strips, GridKind::uniform>(g, pred, i, row, budget);
    else if (!ExactLattice && kind == GridKind::guided)
      w = walk_star_boxes<Walker::warp, ExactLattice, false, false, Strips, GridKind::guided>(g, pred, i, row, budget);
    else if (!ExactLattice && kind == GridKind::guided_tails)
      w = walk_star_boxes<Walker::warp, ExactLattice, false, false, Strips, GridKind::guided_tails>(g, pred, i, row,
                                                                                                   budget);
    else
      w = walk_star_boxes<Walker::warp, ExactLattice, false, false, Strips>(g, pred, i, row, budget);
  } else {
    if (kind == GridKind::uniform)
      w = walk_star_by<Search, ExactLattice, FirstPass, ReadsInbox, Strips, GridKind::uniform>(g, pred, i, row, budget,
                                                                                                inbox);
    else if (!ExactLattice && kind == GridKind::guided)
      w = walk_star_by<Search, ExactLattice, FirstPass, ReadsInbox, Strips, GridKind::guided>(g, pred, i, row, budget,
                                                                                               inbox);
    else if (!ExactLattice && kind == GridKind::guided_tails)
      w = walk_star_by<Search, ExactLattice, FirstPass, ReadsInbox, Strips, GridKind::guided_tails>(g, pred, i, row,
                                                                                                     budget, inbox);
    else
      w = walk_star_by<Search, ExactLattice, FirstPass, ReadsInbox, Strips>(g, pred, i, row, budget, inbox);
  }
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
      if (undecided_list && w.handed_on && cells <= budget)
        undecided_list[atomicAdd(list_counts + 1, 1u)] = i;
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
/// (counted on the CPU, session 13). A warp walks such a site alone, and the last one to finish
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

/// The grid's boundary strips (BoundaryStrips), unsorted: block s gathers side s's sites in
/// cell order (its cells in order, a cell's sites in order) with their keys, and sets length[s]
/// (0 where the room is too small) and the sort's segment of side s, [bounds[s], bounds[4 + s]).
/// Cell order makes the sorted strips, and so the walks' work, the same every run (the sort is
/// stable).
constexpr int kStripThreads = 1024;
__global__ void __launch_bounds__(kStripThreads) boundary_strips_kernel(GridView g, int capacity,
                                                                        std::uint32_t* keys, int* ids, int* length,
                                                                        int* bounds) {
  using Scan = cub::BlockScan<int, kStripThreads>;
  __shared__ typename Scan::TempStorage scan;
  __shared__ int base;
  const int s = static_cast<int>(blockIdx.x);
  const int cells = strip_cells(s, g.gx, g.gy);
  std::uint32_t* const side_keys = keys + static_cast<std::size_t>(s) * capacity;
  int* const side_ids = ids + static_cast<std::size_t>(s) * capacity;
  if (threadIdx.x == 0) base = 0;
  __syncthreads();
  for (int first = 0; first < cells; first += kStripThreads) {
    const int j = first + static_cast<int>(threadIdx.x);
    std::uint32_t begin = 0, end = 0;
    if (j < cells) {
      const int c = strip_cell(s, j, g.gx, g.gy);
      begin = g.cell_start[c];
      end = g.cell_start[c + 1];
    }
    int at = 0, total = 0;
    Scan(scan).ExclusiveSum(static_cast<int>(end - begin), at, total);
    at += base;
    for (std::uint32_t q = begin; q < end; ++q, ++at)
      if (at < capacity) {
        side_keys[at] = strip_key(strip_coordinate(s, g.points[q]));
        side_ids[at] = static_cast<int>(q);
      }
    __syncthreads();
    if (threadIdx.x == 0) base += total;
    __syncthreads();
  }
  if (threadIdx.x == 0) {
    length[s] = base <= capacity ? base : 0;
    bounds[s] = s * capacity;
    bounds[4 + s] = s * capacity + length[s];
  }
}

/// TailColumns' counts: entry j gy + r the sites of cell (the copy's column j, row r), and a
/// last entry of 0, so that their exclusive sum is the copy's starts.
__global__ void tail_counts_kernel(GridView g, int width, std::uint32_t* counts) {
  const int e = blockIdx.x * blockDim.x + threadIdx.x;
  const int entries = 2 * width * g.gy;
  if (e > entries) return;
  if (e == entries) {
    counts[e] = 0;
    return;
  }
  const int j = e / g.gy, r = e - j * g.gy;
  const std::size_t c = static_cast<std::size_t>(r) * g.gx + tail_column_of_grid(j, g.gx, width);
  counts[e] = g.cell_start[c + 1] - g.cell_start[c];
}

/// TailColumns' sites: each cell's, in the grid's order, from its start in the copy.
__global__ void tail_ids_kernel(GridView g, int width, const std::uint32_t* start, int* ids) {
  const int e = blockIdx.x * blockDim.x + threadIdx.x;
  if (e >= 2 * width * g.gy) return;
  const int j = e / g.gy, r = e - j * g.gy;
  const std::size_t c = static_cast<std::size_t>(r) * g.gx + tail_column_of_grid(j, g.gx, width);
  std::uint32_t at = start[e];
  for (std::uint32_t q = g.cell_start[c]; q < g.cell_start[c + 1]; ++q, ++at) ids[at] = static_cast<int>(q);
}

/// Builds g.tail (TailColumns) on `stream` for a grid of quantile cells, in memory the bucketing
/// no longer needs (`key_words`: the counts, the starts and the scan's storage; `id_words`: the
/// sites), as the strips do on equal cells. Leaves g.tail empty where the grid is too small or
/// the words too few.
void build_tail_columns(GridView& g, std::uint32_t* key_words, int* id_words, std::size_t words,
                        cudaStream_t stream) {
  const int width = tail_columns_width(g.gx);
  if (width == 0) return;
  const int entries = 2 * width * g.gy + 1;
  std::size_t temp_bytes = 0;
  EXPANSE_CUDA(cub::DeviceScan::ExclusiveSum(nullptr, temp_bytes, key_words, key_words, entries, stream));
  const std::size_t temp_words = (temp_bytes + 3) / 4 + 64;  // 64 for the storage's 256-byte alignment
  if (2 * static_cast<std::size_t>(entries) + temp_words > words) return;
  std::uint32_t* const counts = key_words;
  std::uint32_t* const start = key_words + entries;
  auto* const temp = reinterpret_cast<unsigned char*>(
      (reinterpret_cast<std::uintptr_t>(key_words + 2 * static_cast<std::size_t>(entries)) + 255) &
      ~std::uintptr_t{255});
  constexpr int threads = 256;
  const int blocks = (entries + threads - 1) / threads;
  tail_counts_kernel<<<blocks, threads, 0, stream>>>(g, width, counts);
  EXPANSE_CUDA(cudaGetLastError());
  EXPANSE_CUDA(cub::DeviceScan::ExclusiveSum(temp, temp_bytes, counts, start, entries, stream));
  tail_ids_kernel<<<blocks, threads, 0, stream>>>(g, width, start, id_words);
  EXPANSE_CUDA(cudaGetLastError());
  g.tail = {start, id_words, width};
}

/// The strips' arrays, in memory the bucketing no longer needs (its unsorted keys and ids: n
/// words each). No allocation of their own: one array more, allocated per triangulation, has
/// moved the bucketing of clustered inputs by a millisecond (kuzmin 4096^2 1.6 -> 2.7 ms, session
/// 24 call 4; session 22 saw the same), the pool placing its arrays elsewhere.
class StripBuffers {
 public:
  StripBuffers(std::uint32_t* key_words, int* id_words, std::size_t words)
      : key_words_(key_words), id_words_(id_words), words_(words) {}
  /// Points g.strips at the arrays for g's grid where they fit: then build() fills them.
  bool prepare(GridView& g, cudaStream_t stream) {
    if (!strips_fit(g.gx, g.gy)) return false;
    capacity_ = strip_capacity(g.gx, g.gy);
    const std::size_t room = 4 * static_cast<std::size_t>(capacity_);
    EXPANSE_CUDA(cub::DeviceSegmentedRadixSort::SortPairs(nullptr, temp_bytes_, static_cast<std::uint32_t*>(nullptr),
                                                          static_cast<std::uint32_t*>(nullptr),
                                                          static_cast<int*>(nullptr), static_cast<int*>(nullptr),
                                                          static_cast<int>(room), 4, static_cast<int*>(nullptr),
                                                          static_cast<int*>(nullptr), 0, 32, stream));
    // The keys' words hold both key arrays and the sort's storage (64 words for its 256-byte
    // alignment); the ids' words both id arrays and length/bounds (12 words, fewer than that).
    const std::size_t temp_words = (temp_bytes_ + 3) / 4 + 64;
    if (2 * room + temp_words > words_) return false;
    keys_ = key_words_;
    sorted_keys_ = key_words_ + room;
    temp_ = reinterpret_cast<unsigned char*>(
        (reinterpret_cast<std::uintptr_t>(key_words_ + 2 * room) + 255) & ~std::uintptr_t{255});
    ids_ = id_words_;
    sorted_ids_ = id_words_ + room;
    length_ = id_words_ + 2 * room;
    bounds_ = length_ + 4;
    g.strips = {sorted_keys_, sorted_ids_, length_, capacity_};
    return true;
  }
  /// Gathers and sorts the strips of g's grid (its cells bucketed), on `stream`.
  void build(const GridView& g, cudaStream_t stream) {
    boundary_strips_kernel<<<4, kStripThreads, 0, stream>>>(g, capacity_, keys_, ids_, length_, bounds_);
    EXPANSE_CUDA(cudaGetLastError());
    std::size_t bytes = temp_bytes_;
    EXPANSE_CUDA(cub::DeviceSegmentedRadixSort::SortPairs(temp_, bytes, keys_, sorted_keys_, ids_, sorted_ids_,
                                                          4 * capacity_, 4, bounds_, bounds_ + 4, 0, 32, stream));
  }

 private:
  std::uint32_t* key_words_;
  int* id_words_;
  std::size_t words_;
  int capacity_ = 0;
  std::size_t temp_bytes_ = 0;
  std::uint32_t *keys_ = nullptr, *sorted_keys_ = nullptr;
  int *ids_ = nullptr, *sorted_ids_ = nullptr, *length_ = nullptr, *bounds_ = nullptr;
  unsigned char* temp_ = nullptr;
};

template <StarSearch Search, int MinBlocks, bool ExactLattice = false, bool FirstPass = false, bool ReadsInbox = false>
__global__ void __launch_bounds__(128, MinBlocks) star_kernel(GridView g, const int* pred, int n, int* star,
                                                              std::uint32_t* info, int* owned,
                                                              unsigned int* counters, unsigned budget,
                                                              const int* order, WalkPass pass, int* retry_list,
                                                              int* undecided_list, EdgeCells edge,
                                                              int phases, int phase, StarInbox inbox,
                                                              bool ends_first = false) {
  // Thread t walks local site order[t], or the t-th site of its phase (StarInbox): cell order
  // measured faster than the sites' Morton order on the H100 (uniform 4096^2: 230 vs 244 ms;
  // kuzmin: 629 vs 733 ms). Morton order walks in one phase.
  const int b = ends_first ? ends_first_block(static_cast<int>(blockIdx.x), static_cast<int>(gridDim.x))
                           : static_cast<int>(blockIdx.x);
  const int t = (b * static_cast<int>(blockDim.x) + static_cast<int>(threadIdx.x)) * phases + phase;
  if (t >= n) return;
  const int i = order ? order[t] : t;
  if (edge.holds(i)) return;  // the edge stream walks it
  walk_and_record<Search, Walker::thread, ExactLattice, FirstPass, ReadsInbox>(
      g, pred, i, star, info, owned, counters, budget, pass, retry_list, undecided_list, counters + 7, inbox);
}

/// The sites list[0 .. *count), a thread each, as a first pass walks them: those that run past
/// `budget` go on to the warps (retry_list), and with the light walk (FirstPass) those that meet
/// an undecided candidate to undecided_list; list_counts as walk_and_record's. Grid-stride, so
/// that a short list costs one small launch. Two uses:
///  - the light first pass's undecided sites, walked in full (with the exact path) under the
///    first pass's budget. Nearly cocircular float inputs (decimal grids) send nearly every site
///    here: a warp each they took 115 ms at 1024^2 (H100, session 12 call 3);
///  - the first pass of the grid's edge (EdgeCells), on its own stream.
///  - the second phase's sites that need a search (inbox_star_kernel), reading their inboxes
///    (ReadsInbox), in the phase's pass.
template <StarSearch Search, int MinBlocks, bool ExactLattice = false, bool FirstPass = false, bool ReadsInbox = false,
          bool Strips = false>
__global__ void __launch_bounds__(128, MinBlocks) star_list_kernel(GridView g, const int* pred, int* star,
                                                                   std::uint32_t* info, int* owned,
                                                                   unsigned int* counters, unsigned budget,
                                                                   const int* list, const unsigned int* count,
                                                                   int* retry_list, int* undecided_list,
                                                                   unsigned int* list_counts,
                                                                   WalkPass pass = WalkPass::first,
                                                                   StarInbox inbox = {}) {
  const unsigned sites = *count;
  for (unsigned k = blockIdx.x * blockDim.x + threadIdx.x; k < sites; k += gridDim.x * blockDim.x)
    walk_and_record<Search, Walker::thread, ExactLattice, FirstPass, ReadsInbox, Strips>(
        g, pred, list[k], star, info, owned, counters, budget, pass, retry_list, undecided_list, list_counts, inbox);
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
    // writing the row as it went, this kernel took 1.76 ms instead of 1.15 at 4096^2 uniform:
    // H100, session 33 call 4.)
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
template <StarSearch Search, int MinBlocks, bool ExactLattice = false, bool Strips = false>
__global__ void __launch_bounds__(128, MinBlocks) star_retry_kernel(GridView g, const int* pred, int* star,
                                                                    std::uint32_t* info, int* owned,
                                                                    unsigned int* counters, unsigned budget,
                                                                    const int* retry_list, const unsigned int* count,
                                                                    const unsigned int* skip = nullptr) {
  const unsigned sites = *count;
  const unsigned warps = gridDim.x * (blockDim.x / 32);
  for (unsigned k = (skip ? *skip : 0u) + (blockIdx.x * blockDim.x + threadIdx.x) / 32; k < sites; k += warps)
    walk_and_record<Search, Walker::warp, ExactLattice, false, false, Strips>(
        g, pred, retry_list[k], star, info, owned, counters, budget, WalkPass::retry, nullptr, nullptr, nullptr);
}

// The emit (scan's offsets -> triangles and neighbours) in two kernels, a thread per site and
// then a thread per triangle: one thread a site, linking each of its triangles by searching the
// stars around it, ran at 5.7 of a warp's 32 threads and took 7.0 ms at 4096^2 uniform under
// ncu (H100, session 14 call 2), its loops as uneven as the stars. Both read stars through
// StarView (star_view.cuh).

/// Blocks of kEmitSites sites for the triangles' kernel: a block's triangles are one contiguous
/// range of the output (offset[first] to offset[last]), staged in shared memory kEmitRoom at a
/// time and written in whole sectors (written by their sites, a thread's ~2 triangles at a time,
/// each 4-byte store was a sector of its own: 97 M sectors through L2 for 400 MB of triangles,
/// session 23 call 1; 17 M staged, call 2). Staged alone the kernel kept its 1.67 ms, its
/// star reads holding it; with StarView, 0.80 ms (ncu, 4096^2 uniform, call 3).
constexpr int kEmitSites = 128;
constexpr int kEmitRoom = 1024;  // ~4 times what a block's sites own at ~2 triangles each

/// emit_triangles_kernel: site i's owned triangles (it is their smallest vertex), in site ids, at
/// offset[i] on; owned[i] the bitmask of its star's triangles it owns (bit t: the triangle (i,
/// star t, star t + 1)), so that any triangle's output index is its owner's offset plus the
/// owned triangles before it in the owner's star. Past `capacity` (more triangles than a
/// triangulation has: a broken walk, which the host then reports) no triangle is written.
__global__ void __launch_bounds__(kEmitSites) emit_triangles_kernel(const int* star, const std::uint32_t* info,
                                                                    const int* offset, const int* sorted_ids, int n,
                                                                    int capacity, int* triangles,
                                                                    std::uint32_t* owned) {
  __shared__ int staged[3 * kEmitRoom];
  const int first = blockIdx.x * kEmitSites, last = min(first + kEmitSites, n);
  const int i = first + static_cast<int>(threadIdx.x);
  const std::uint32_t inf = i < n ? info[i] : kDeferredBit;
  const bool live = !star_deferred(inf);
  const StarView view(star, inf, i);  // a deferred site's (degree 0) loads and reads nothing
  std::uint32_t mask = 0;
  if (live) mask = view.owned_mask();
  if (i < n) owned[i] = mask;
  const int first_index = i < n ? offset[i] : 0;
  const int id = i < n ? sorted_ids[i] : -1;
  const int end = min(offset[last], capacity);
  for (int chunk = offset[first]; chunk < end; chunk += kEmitRoom) {  // the same rounds for the whole block
    const int chunk_end = min(chunk + kEmitRoom, end);
    int index = first_index;
    for (std::uint32_t m = mask; m != 0u && index < chunk_end; m &= m - 1u, ++index) {
      if (index < chunk) continue;
      const int t = __ffs(static_cast<int>(m)) - 1;
      int* tri = staged + 3 * (index - chunk);
      tri[0] = id;
      tri[1] = sorted_ids[view.at(t)];
      tri[2] = sorted_ids[view.at(t + 1)];
    }
    __syncthreads();
    int* out = triangles + 3 * static_cast<std::size_t>(chunk);
    for (int k = static_cast<int>(threadIdx.x); k < 3 * (chunk_end - chunk); k += kEmitSites) out[k] = staged[k];
    __syncthreads();
  }
}

/// Output index of triangle q of non-deferred site o's star (the triangle (o, star q, star q + 1)),
/// when o owns it; -1 when not (its owner is one of the other two).
__device__ __forceinline__ int owned_triangle_index(const int* offset, const std::uint32_t* owned, int o, int q) {
  const std::uint32_t mask = owned[o];
  return (mask >> q) & 1u ? offset[o] + __popc(mask & ((1u << q) - 1u)) : -1;
}

/// Index of the CCW triangle (x, y, z) in the output: its owner o is its smallest vertex, and
/// (o, u, w) is the triangle at u's position q in o's star; -1 if o deferred (or the stars
/// disagree, which the audit then reports).
__device__ int triangle_index(const int* star, const std::uint32_t* info, const int* offset,
                              const std::uint32_t* owned, int x, int y, int z) {
  int o = x, u = y, w = z;
  if (y < o && y < z) {
    o = y, u = z, w = x;
  } else if (z < o && z < y) {
    o = z, u = x, w = y;
  }
  const std::uint32_t inf = info[o];
  if (star_deferred(inf)) return -1;
  const StarView view(star, inf, o);
  const int q = view.find(u);
  if (q < 0 || q >= view.triangles() || view.at(q + 1) != w) return -1;
  return owned_triangle_index(offset, owned, o, q);
}

/// Triangle k's three neighbours (-1 where there is none, or its owner deferred): neighbour j
/// lies across the edge opposite vertex j. Its owner is its first vertex (rank: site id -> local
/// id), and its place in the owner's star the owned bit of its rank among the owner's triangles.
/// A neighbour is also a triangle of a star already at hand (the owner's, on either side of k;
/// the one found across the edge opposite the owner): where that star's site owns it, its index
/// is that site's owned bits, with no search of its owner's star (`known_places`; false searches
/// as before, for comparisons). Tried and not kept (session 23): the triangles' places staged by
/// block instead, no read-back of the triangles and no rank look-up, 1.83 -> 2.23 ms under ncu
/// (call 2); each place left by the triangles' kernel in the triangle's neighbour words, the
/// emit 2.54 ms (call 4) against 2.50 without (call 3, another H100).
__global__ void __launch_bounds__(128) emit_neighbors_kernel(const int* star, const std::uint32_t* info,
                                                             const int* offset, const std::uint32_t* owned,
                                                             const int* triangles, const int* rank, int n,
                                                             int capacity, int* neighbors, bool known_places) {
  const int k = blockIdx.x * blockDim.x + threadIdx.x;
  const int total = offset[n];
  if (k >= total || total > capacity) return;
  const int i = rank[triangles[3 * static_cast<std::size_t>(k)]];
  const int t = static_cast<int>(__fns(owned[i], 0, k - offset[i] + 1));
  int* nb = neighbors + 3 * static_cast<std::size_t>(k);
  const StarView own(star, info[i], i);
  const int deg = own.degree();
  const bool closed = own.closed();
  const int a = own.at(t), b = own.at(t + 1);
  int across_ab = -1;  // opposite i: the triangle (b, a, r)
  int r = -1;
  const std::uint32_t ia = info[a], ib = info[b];
  if (!star_deferred(ia)) {
    const StarView at_a(star, ia, a);
    const int p = at_a.find(b);
    if (p >= 0 && (p > 0 || at_a.closed())) {
      const int q = p > 0 ? p - 1 : at_a.degree() - 1;  // (a, r, b) is a's triangle q
      r = at_a.at(q);
      if (known_places) across_ab = owned_triangle_index(offset, owned, a, q);
    }
  } else if (!star_deferred(ib)) {
    const StarView at_b(star, ib, b);
    const int q = at_b.find(a);  // (b, a, r) is b's triangle q
    if (q >= 0 && (q < at_b.degree() - 1 || at_b.closed())) {
      r = at_b.at(q + 1);
      if (known_places) across_ab = owned_triangle_index(offset, owned, b, q);
    }
  }
  if (r >= 0 && across_ab < 0) across_ab = triangle_index(star, info, offset, owned, b, a, r);
  int across_bi = -1;  // opposite a: (i, b, next), i's triangle t + 1
  if (closed || t + 2 < deg) {
    if (known_places) across_bi = owned_triangle_index(offset, owned, i, t + 1 < deg ? t + 1 : 0);
    if (across_bi < 0) across_bi = triangle_index(star, info, offset, owned, i, b, own.at(t + 2));
  }
  int across_ia = -1;  // opposite b: (i, previous, a), i's triangle t - 1
  if (closed || t >= 1) {
    if (known_places) across_ia = owned_triangle_index(offset, owned, i, t >= 1 ? t - 1 : deg - 1);
    if (across_ia < 0) across_ia = triangle_index(star, info, offset, owned, i, own.at(t - 1), a);
  }
  nb[0] = across_ab;
  nb[1] = across_bi;
  nb[2] = across_ia;
}

/// The host audit's checks (seam/adjacency_audit.cpp) where the adjacency is made, before it
/// crosses the bus: every link leads to a triangle that holds the same edge the other way round
/// and links back across it; a missing link must be a hull edge (pred[] is in local ids, the
/// triangles in site ids) or the seam's. result[0] counts bad links, result[1] open edges inside
/// the hull; with `open_keys`, those edges are also listed (x << 32 | y, result[2] counting),
/// and where they are (3 t + k: triangle t's link k) in open_slots.
/// Random reads of 805 MB take the host's cores ~300 ms at 4096^2; the device's memory, 0.4 ms.
__global__ void audit_kernel(const int* triangles, const int* neighbors, int count, const int* rank, const int* pred,
                             unsigned int* result, std::uint64_t* open_keys, int* open_slots, unsigned open_room) {
  const int t = blockIdx.x * blockDim.x + threadIdx.x;
  if (t >= count) return;
  unsigned bad = 0, open = 0;
  for (int k = 0; k < 3; ++k) {
    const int x = triangles[3 * static_cast<std::size_t>(t) + (k + 1) % 3];
    const int y = triangles[3 * static_cast<std::size_t>(t) + (k + 2) % 3];
    const int u = neighbors[3 * static_cast<std::size_t>(t) + k];
    if (u == -1) {
      if (pred[rank[y]] != rank[x]) {  // not x->y on the hull (y's predecessor is x)
        ++open;
        if (open_keys) {
          const unsigned at = atomicAdd(result + 2, 1u);
          if (at < open_room) {  // past it only counted: the host lists them again with room for all
            open_keys[at] = (static_cast<std::uint64_t>(x) << 32) | static_cast<std::uint32_t>(y);
            open_slots[at] = 3 * t + k;
          }
        }
      }
      continue;
    }
    if (u < 0 || u >= count) {
      ++bad;
      continue;
    }
    int j = 0;
    while (j < 3 && !(triangles[3 * static_cast<std::size_t>(u) + (j + 1) % 3] == y &&
                      triangles[3 * static_cast<std::size_t>(u) + (j + 2) % 3] == x))
      ++j;
    bad += j == 3 || neighbors[3 * static_cast<std::size_t>(u) + j] != t;
  }
  if (bad) atomicAdd(result, bad);
  if (open) atomicAdd(result + 1, open);
}

/// Open edges in pairs: x->y open in one triangle and y->x in another. Both triangles are made
/// (every triangle emitted is Delaunay), but the sites whose stars would have linked them
/// deferred, so emit_neighbors_kernel left both links out. They are neighbours: link them, both
/// ways. `sorted` holds every open edge, sorted, and `slots` where each is. result[3] counts the
/// links made; result[0] an edge listed twice (two triangles with the same edge the same way
/// round: a broken triangulation, which the pipeline must not trust). An edge without its
/// reverse stays open: its slot goes to still_open (result[2] counting), for the seam stage.
/// The links pair edges that the audit found open and leave every other link as the audit
/// passed it, so the adjacency needs no second audit.
__global__ void link_open_pairs_kernel(const std::uint64_t* sorted, const int* slots, unsigned count, int* neighbors,
                                       unsigned int* result, int* still_open) {
  const unsigned k = blockIdx.x * blockDim.x + threadIdx.x;
  if (k >= count) return;
  if (k + 1 < count && sorted[k + 1] == sorted[k]) atomicAdd(result, 1u);
  const std::uint64_t reverse = (sorted[k] << 32) | (sorted[k] >> 32);
  unsigned lo = 0, hi = count;
  while (lo < hi) {
    const unsigned mid = (lo + hi) / 2;
    if (sorted[mid] < reverse) lo = mid + 1;
    else hi = mid;
  }
  if (lo < count && sorted[lo] == reverse) {
    neighbors[slots[k]] = slots[lo] / 3;
    atomicAdd(result + 3, 1u);
  } else {
    still_open[atomicAdd(result + 2, 1u)] = slots[k];
  }
}

constexpr int kThreads = 256;

/// The first pass's work budget (WalkPass). What it leaves, the warps of the second pass walk 32
/// candidates at a time, so the smaller the better while the second pass stays short. Measured
/// on the H100 in one run (2026-11-23, star kernel, 4096^2 / 512^2): one pass 154 / 13.7 ms
/// uniform, 506 / 30.2 kuzmin; first budget 2^12: 105 / 11.4, 161 / 18.7; 2^10: 100 / 8.7,
/// 147 / 6.0 (cuda_backend/results/2026-11-23-h100-s4, call 3). Small inputs fill few waves, and
/// their kernel is the tail of their heaviest sites: at 512^2 a budget of 2^8 gave 7.2 / 5.7 /
/// 5.1 / 5.4 ms (uniform / gaussian / grid / kuzmin) against 8.7 / 7.8 / 5.2 / 6.0 at 2^10; at
/// 4096^2 it lost (gaussian 130 against 104, kuzmin 259 against 148; 2^9: 98 / 105 / 330 / 166
/// against 100 / 104 / 330 / 148), session 5 call 4. Between the two sizes it is not measured.
/// On quantile cells (clustered inputs) 2^11 above 2^20 sites: kuzmin's searches in the cells
/// its Cauchy marginals stretch run a little past 2^10 by the ten thousand (counted on the CPU,
/// 4M sites: 13,451 of the 22,434 over 2^10 need at most 2^11), and a warp walks each again from
/// the start. H100, star kernels, alternated (session 14 calls 2-3): kuzmin 4096^2 81.6 -> 77.5
/// ms, 2048^2 22.0-23.2 -> 21.2-21.5, but 1024^2 7.3-7.5 -> 7.9-8.3; gaussian 4096^2 62.7 ->
/// 62.3, 2048^2 23.45 -> 23.75. Uniform inputs, on uniform cells, had lost 2% (session 13
/// call 2). And 2^12 above 2^23 sites: the larger the input, the longer its stretched cells, and
/// at 4096^2 kuzmin has 12,570 sites between 2^11 and 2^12 units (counted on the CPU) that a warp
/// walked again from the start. H100, GPU-only, two rounds (session 17 call 6, with the interior
/// retry at 2^13), 2^11 / 3 * 2^10 / 2^12: kuzmin 4096^2 72.6-72.8 / 71.0-71.4 / 69.8-70.0 ms,
/// gaussian 4096^2 49.1-50.1 / 49.9-52.7 / 50.4-50.7; at 2048^2 2^12 lost (kuzmin 23.3-23.7 ->
/// 25.1-25.5, gaussian 17.8-17.9 -> 18.7). Since heavy tails are weighed (quantile_tails), those
/// stretched cells are fewer, and 2^11 serves above 2^23 sites too (session 25 calls 5-6,
/// GPU-only, two rounds each: kuzmin 4096^2 60.07 / 60.08 -> 59.51 / 59.34 ms at the weighing of
/// 40,5; gaussian 44.84 / 44.90 -> 44.36 / 44.31 and, with 2^10, 44.77 / 44.69).
unsigned first_pass_budget(std::size_t sites, bool quantile_cells) {
  if (sites <= (std::size_t{1} << 18)) return 1u << 8;
  if (!quantile_cells || sites <= (std::size_t{1} << 20)) return 1u << 10;
  return 1u << 11;
}
/// The whole walk's budget for box scans (default_budget above 2^20 sites). Up to 2^20 sites the
/// kernel is the tail of its few heaviest sites, the hull-hugging ones, and the seam stage makes
/// their triangles for less: budget 2^13 against 2^16 (H100, 2026-11-24, session 6 call 4, star
/// kernel): 512^2 uniform 3.5 against 5.3 ms, gaussian 4.0 / 4.4, grid and kuzmin unchanged;
/// 1024^2 uniform 8.4 / 11.6, gaussian 7.6 / 16.5; seam share at most 0.03% (uniform 1024^2,
/// 123 sites deferred). 2^12 was faster still at 512^2 (uniform 3.3 ms) but deferred kuzmin's
/// sites by the hundred (0.06%, 0.07% at 1024^2), and at 4096^2 by the ten thousand (0.13%).
unsigned box_search_budget(std::size_t sites) {
  return sites <= (std::size_t{1} << 20) ? 1u << 13 : default_budget(StarSearch::boxes);
}
/// The second pass's budget for the sites away from the grid's edge (the edge's stream keeps the
/// whole budget). Such a site runs long only in a sparse stretch of a clustered input, where the
/// quantile cells are long and thin, and a lone warp walking one for 2^16 units held the stage
/// for as long as 12 ms after everything else was done; the seam stage makes its triangles for
/// far less. H100, 4096^2, GPU-only, two rounds (session 17 call 4), retry budget 2^16 / 2^15 /
/// 2^14 / 2^13: gaussian 60.3 / 56.4 / 54.4 / 50.0 ms (7 / 8 / 12 / 22 sites deferred, the
/// seam's growth 0.2 -> 0.5 ms), kuzmin 73.7 / 73.6 / 73.1 / 72.5 (41 / 135 / 661 / 1,737
/// deferred: 0.012% of the triangles; the seam's growth 0.3 -> 6-10 ms on one host core, beside
/// the output's remapping); uniform (no such site) unchanged; 2048^2 gaussian 25.2 -> 17.7.
/// Hull-hugging sites are another matter (uniform 4096^2: 76 of them cost the seam 9 ms): they
/// are the edge's. Up to 2^20 sites the whole budget is 2^13 already.
unsigned interior_retry_budget(unsigned budget) { return std::min(budget, 1u << 13); }

/// Blocks of 128 threads a multiprocessor that the star kernels' registers allow (4, 6 or 8):
/// the first phase's (and the main stream's lists of sites to walk again), the second
/// phase's, and the edge stream's (EdgeCells).
struct StarBlocks {
  int first, later, edge;
};
/// "F,L,E", or "B" for every group (any other text: its first number for every group).
StarBlocks parse_star_blocks(const char* text) {
  int v[3] = {0, 0, 0};
  const int got = std::sscanf(text, "%d,%d,%d", &v[0], &v[1], &v[2]);
  return got == 3 ? StarBlocks{v[0], v[1], v[2]} : StarBlocks{v[0], v[0], v[0]};
}
/// f(std::integral_constant<int, 4, 6 or 8>): the kernels are compiled for these three.
template <class F>
void with_star_blocks(int blocks, F&& f) {
  if (blocks >= 8)
    f(std::integral_constant<int, 8>{});
  else if (blocks <= 4)
    f(std::integral_constant<int, 4>{});
  else
    f(std::integral_constant<int, 6>{});
}
/// Device memory per site of the star layout: points twice, cell keys and ids twice, rank,
/// predecessor, owned, offset, retry, undecided; the star row; triangles and neighbours (about 2
/// a site); an inbox (StarInbox) for every other site.
std::size_t per_site_bytes() {
  return 2 * sizeof(double2) + 2 * 2 * sizeof(std::uint32_t) + 9 * sizeof(int) + kStar * sizeof(int) +
         2 * 2 * 3 * sizeof(int) + sizeof(int) + (kInboxWords + 1) * sizeof(int) / 2 + 64;
}
int blocks_for(std::size_t n, int threads = kThreads) { return static_cast<int>((n + threads - 1) / threads); }

}  // namespace

void grow_per_site(Context& ctx, const GrowInput& input, GrowResult& result, const SitesOnDevice* on_device) {
  const cudaStream_t stream = ctx.stream;
  const auto& points = input.sites.points;
  const std::size_t n = points.size();
  if (n >= (std::size_t{1} << 30))
    throw Error(ErrorCode::too_large, "CUDA backend: more than 2^30 sites (triangle ids would overflow)");

  const GridShape shape = make_grid_shape(input.sites.bounds, n, input.layout.sites_per_bucket);
  const std::size_t cells = static_cast<std::size_t>(shape.gx) * shape.gy;

  // Fail early, with the right error, when the working set cannot fit.
  require_device_memory(n * per_site_bytes() + cells * sizeof(std::uint32_t), n, "sites");

  StageTimer timer(stream);
  const auto host_start = Clock::now();
  DeviceArray<double2> d_uploaded_points(on_device ? 0 : n, stream);
  DeviceArray<int> d_uploaded_hull(on_device ? 0 : input.hull.sites.size(), stream);
  const double2* d_points = on_device ? on_device->points : d_uploaded_points.get();
  const int* d_hull = on_device ? on_device->hull : d_uploaded_hull.get();
  if (!on_device) {
    timer.begin("upload");
    static_assert(sizeof(Point2) == sizeof(double2));
    ctx.staging->upload(d_uploaded_points.get(), points.data(), n * sizeof(double2), stream);
    ctx.staging->upload(d_uploaded_hull.get(), input.hull.sites.data(), d_uploaded_hull.bytes(), stream);
    timer.end();
  }
  const auto host_uploaded = Clock::now();

  const GridShape uniform_shape =
      uniform_cells_shape(input.sites.bounds, n, input.layout.sites_per_bucket, input.sites.integer_coordinates);
  CellBuckets buckets(n, shape, uniform_shape, stream);
  DeviceArray<int> d_rank(n, stream), d_pred(n, stream);
  DeviceArray<int> d_star(n * kStar, stream);
  DeviceArray<std::uint32_t> d_info(n, stream);
  DeviceArray<int> d_owned(n, stream), d_offset(n + 1, stream);
  // [9..11]: the edge's lists (EdgeCells); [12]: the second phase's sites that search; [13]: the
  // retry list's length after the first phase (launch_first_phase_retry)
  DeviceArray<unsigned int> d_counters(14, stream);
  DeviceArray<int> d_retry(n, stream);  // sites the first star pass leaves to the second
  const int* d_sorted_ids = buckets.sorted_ids.get();

  // EXPANSE_CUDA_BUDGET sets the per-site work budget (cells + sites visited) past which a site
  // defers to the seam stage.
  const char* budget_env = std::getenv("EXPANSE_CUDA_BUDGET");
  // EXPANSE_CUDA_SEARCH=rings selects the ring searches of star_walk.cuh (for comparisons).
  const char* search_env = std::getenv("EXPANSE_CUDA_SEARCH");
  const bool rings = search_env && std::strcmp(search_env, "rings") == 0;
  const unsigned budget = budget_env ? static_cast<unsigned>(std::strtoul(budget_env, nullptr, 10))
                          : rings    ? default_budget(StarSearch::rings)
                                     : box_search_budget(n);

  std::size_t scan_bytes = 0;
  EXPANSE_CUDA(cub::DeviceScan::InclusiveSum(nullptr, scan_bytes, d_owned.get(), d_offset.get() + 1,
                                             static_cast<int>(n), stream));
  DeviceArray<unsigned char> d_temp(scan_bytes, stream);

  GridView g = make_grid_view(shape, input.sites.bounds);
  // The boundary strips (BoundaryStrips) for the searches along the grid's outer columns and
  // rows, from 2^16 sites (EXPANSE_CUDA_STRIPS=0: none, for comparisons; =1: at any size, for the
  // tests).
  const char* strips_env = std::getenv("EXPANSE_CUDA_STRIPS");
  const bool strips_on = !rings && (strips_env ? std::strcmp(strips_env, "0") != 0 : n >= (std::size_t{1} << 16));
  StripBuffers strips(buckets.keys.get(), buckets.ids.get(), n);
  // EXPANSE_CUDA_EXACT_LATTICE=0 takes small lattices through the filters and the exact path
  // as any input (for comparisons).
  const char* lattice_env = std::getenv("EXPANSE_CUDA_EXACT_LATTICE");
  const bool exact_lattice =
      exact_lattice_arithmetic(input.sites) && !(lattice_env && std::strcmp(lattice_env, "0") == 0);

  timer.begin("bucket");
  // The evenness test's read-back goes through pinned word 15, the guides' keys through words
  // 16..31, each read at once (the audit reuses word 15 later).
  static_assert(2 * sizeof(QuantileGuideKey) == 16 * sizeof(unsigned int));
  buckets.build(g, d_points, static_cast<int>(n), d_rank.get(), on_device && on_device->unordered_runs,
                &ctx.pinned_words[15],
                reinterpret_cast<QuantileGuideKey*>(&ctx.pinned_words[16]), &ctx.pinned_words[14], stream);
  apply_first_box(g, buckets.uniform(), input.sites);
  // Quantile cells' outer columns copied column after column, for the searches whose boxes run
  // tall in them, where the x-axis has heavy tails (TailColumns; EXPANSE_CUDA_TAIL_COLUMNS=0:
  // none, =1: on any quantile cells with guides, both for comparisons).
  if (!buckets.uniform() && !rings && tail_columns_wanted(buckets.heavy_x_tails()) && g.x_guide.first &&
      g.y_guide.first)
    build_tail_columns(g, buckets.keys.get(), buckets.ids.get(), n, stream);
  // Strips for grids of equal cells over inputs that are no small lattice: a uniform square's
  // hull-hugging sites. Quantile cells' outer rows and columns hold a clustered input's sparse
  // tails, where the strips' scattered reads lost: kuzmin 4096^2 GPU-only 66.7 -> 69.6 ms, the
  // edge's stream 45 -> 57 ms (session 24 call 3). A lattice gained nothing (its hull sides hold
  // sites, no slivers) and paid the build.
  const bool strip_walks = strips_on && buckets.uniform() && !exact_lattice && strips.prepare(g, stream);
  EXPANSE_CUDA(cudaMemsetAsync(d_pred.get(), 0xff, d_pred.bytes(), stream));
  if (!input.hull.sites.empty()) {
    hull_predecessor_kernel<<<blocks_for(input.hull.sites.size()), kThreads, 0, stream>>>(
        d_hull, static_cast<int>(input.hull.sites.size()), d_rank.get(), d_pred.get());
    EXPANSE_CUDA(cudaGetLastError());
  }
  EXPANSE_CUDA(cudaMemsetAsync(d_counters.get(), 0, d_counters.bytes(), stream));
  EXPANSE_CUDA(cudaMemsetAsync(d_offset.get(), 0, sizeof(int), stream));
  timer.end();

  timer.begin("stars");
  StreamTimeline timeline;
  timeline.mark("stage", stream);  // the walks' set-up before "start"
  // EXPANSE_CUDA_BLOCKS_PER_SM (4, 6 or 8) caps the star kernel's registers so that that many
  // blocks of 128 threads fit on a multiprocessor (65536 / (128 * blocks) registers a thread:
  // 64 at 8, 80 at 6, 128 at 4). 6 for integer coordinates: a lattice's cocircular cells send most
  // candidates to the out-of-line exact decision, and the registers live across that call
  // spill at 64. H100, 2026-11-24 (session 6 call 7, star kernel, 6 against 8, one run):
  // grid 4096^2 252.8 against 308.0 ms, 2048^2 63.5 / 77.4, 512^2 4.00 / 4.83; uniform 78.1 /
  // 78.2 at 4096^2; but kuzmin 172.7 / 158.6, so not for every input. On uniform cells 6 is
  // faster for uniform inputs too (session 7 call 9, star kernel, 6 against 8, two rounds):
  // 4096^2 62.4 / 66.1 ms, 2048^2 23.2 / 24.5, 512^2 2.68 / 2.82; kuzmin, on quantile cells,
  // still loses (169 / 159). So 6 for uniform cells or integer coordinates, until the first
  // pass walked light: then 8 won on uniform cells too (session 11 call 12, star kernel, 8
  // against 6, two rounds: uniform 4096^2 47.7 / 49.9 ms, 512^2 2.31 / 2.27; gaussian and
  // kuzmin, on quantile cells, 63.1 / 66.5 and 95.8 / 104.3). Integer coordinates that are not
  // a small lattice were not measured again and keep 6. Since then (the phases, the first
  // box, the ends-first order) 6 has won back uniform cells at every size (session 20 call 4,
  // GPU-only, 6 against 8, two rounds: 512^2 2.59 / 2.56 against 2.65 / 2.61 ms, 1024^2 4.91 /
  // 4.92 against 5.11 / 5.15, 2048^2 17.05 / 16.85 against 18.47 / 18.48, 4096^2 38.62 / 38.64
  // against 39.15 / 39.14), and 4 (128 registers) wins up to 2048^2 (calls 5 and 6, GPU-only,
  // two rounds each, 4 / 5 / 6 / 8 blocks: 512^2 2.54 / 2.57 / 2.62 / 2.72 ms, 1024^2 4.59 / 4.68 /
  // 4.97 / 5.10, 2048^2 15.6 / 16.4 / 17.0 / 18.4, but 2896^2 23.4 / 22.3 / 21.5 / 23.3 and
  // 4096^2 42.7 / 40.3 / 38.7 / 39.2): below ~2^22 sites the points fit in L2 and a thread's
  // registers matter more than how many threads hide memory's latency. Above, the kernel groups
  // differ (call 7's timelines at 4096^2 uniform: the first phase ends at 22.9 ms with 8 blocks
  // against 23.6 with 6, the second takes 8.2 ms with 6 against 9.4 with 8), so each group has
  // its own count (StarBlocks; call 8, GPU-only, two rounds): uniform 4096^2 8,6,6 37.67 / 37.69
  // ms against 6,6,6 38.65 / 38.65. Up to 2^22 sites uniform cells keep 4 everywhere (2048^2:
  // 4,4,4 15.37 / 15.47 against 8,6,4 16.59 / 16.70). Quantile cells keep 8 everywhere: a
  // second phase at 6 gained gaussian 0.7 ms at 4096^2 (47.73 / 47.73 against 48.47 / 48.45) but
  // lost kuzmin as much (call 9, three rounds alternated: 69.92 / 69.56 / 71.02 against 69.90 /
  // 69.40 / 68.91 ms), and kuzmin is the input furthest from its goal; kuzmin also lost below 8
  // in the first phase (call 6: 2048^2 22.5 ms at 8 against 23.1-25.0). Seven blocks (72
  // registers, compiled in place of 6 for the trial) lost to eight on uniform cells (session 33
  // call 3, 4096^2 GPU-only: 7,7,7 31.78 / 31.81 ms, 8,7,7 31.49 / 31.40, 8,6,6 31.34 / 31.38).
  const bool uniform_floats = buckets.uniform() && !input.sites.integer_coordinates;
  StarBlocks star_blocks = uniform_floats                    ? (n <= (std::size_t{1} << 22) ? StarBlocks{4, 4, 4}
                                                                                            : StarBlocks{8, 6, 6})
                           : input.sites.integer_coordinates ? StarBlocks{6, 6, 6}
                                                             : StarBlocks{8, 8, 8};
  // EXPANSE_CUDA_BLOCKS_PER_SM=B sets every star kernel's; =F,L,E the first phase's (and the
  // main stream's lists), the second phase's and the edge stream's apart.
  if (const char* blocks_env = std::getenv("EXPANSE_CUDA_BLOCKS_PER_SM")) star_blocks = parse_star_blocks(blocks_env);
  // The sites are walked in two passes (WalkPass): the first, a thread per site, with budget
  // first_pass_budget (EXPANSE_CUDA_FIRST_BUDGET; 0: one pass with the full budget).
  const char* first_env = std::getenv("EXPANSE_CUDA_FIRST_BUDGET");
  const unsigned first_budget = rings       ? 0u
                                : first_env ? static_cast<unsigned>(std::strtoul(first_env, nullptr, 10))
                                            : first_pass_budget(n, !buckets.uniform());
  const bool two_passes = first_budget > 0 && first_budget < budget;
  // EXPANSE_CUDA_ORDER=morton runs the threads in the sites' Morton order (prepare_sites sorts
  // them so; rank maps a site to its local id) instead of cell order.
  const char* order_env = std::getenv("EXPANSE_CUDA_ORDER");
  const int* order = order_env && std::strcmp(order_env, "morton") == 0 ? d_rank.get() : nullptr;
  // The first pass walks light (walk_star_boxes' FirstPass) unless the input is integer but no
  // small lattice: there the filters leave the cocircular cells of nearly every site undecided,
  // and a light pass would hand nearly all of them to the second, a warp a site (a 120 x 120
  // grid 100 units apart hands on every site). EXPANSE_CUDA_FIRST_WALK=full gives the first
  // pass the full walk for any input, for comparisons.
  const char* first_walk_env = std::getenv("EXPANSE_CUDA_FIRST_WALK");
  const bool first_full = (first_walk_env && std::strcmp(first_walk_env, "full") == 0) ||
                          (input.sites.integer_coordinates && !exact_lattice);
  const int retry_blocks = 8 * ctx.multiprocessors;
  DeviceArray<int> d_undecided(two_passes && !first_full ? n : 0, stream);
  const WalkPass pass = two_passes ? WalkPass::first : WalkPass::only;
  const unsigned pass_budget = two_passes ? first_budget : budget;
  if (rings) {
    star_kernel<StarSearch::rings, 1><<<blocks_for(n, 128), 128, 0, stream>>>(
        g, d_pred.get(), static_cast<int>(n), d_star.get(), d_info.get(), d_owned.get(), d_counters.get(), budget,
        order, WalkPass::only, nullptr, nullptr, EdgeCells{}, 1, 0, StarInbox{});
  } else {
    // The sites of the grid's outer ring of cells (EdgeCells) take their two passes on the edge
    // stream while the rest take theirs here; EXPANSE_CUDA_EDGE_DEPTH sets how many rings (0:
    // none, every site here). Only with a stream of our own (a lent stream keeps all the work)
    // and two passes in cell order.
    const char* edge_env = std::getenv("EXPANSE_CUDA_EDGE_DEPTH");
    const int edge_depth =
        ctx.edge_stream && two_passes && !order ? (edge_env ? std::max(0, std::atoi(edge_env)) : 1) : 0;
    const EdgeCells edge =
        edge_depth > 0 ? EdgeCells{buckets.keys_sorted.get(), g.gx, g.gy, edge_depth} : EdgeCells{};
    // The second pass of the sites the edge's stream does not take: interior_retry_budget
    // (EXPANSE_CUDA_RETRY_BUDGET); with no edge set apart, every site's is `budget`.
    const char* retry_env = std::getenv("EXPANSE_CUDA_RETRY_BUDGET");
    const unsigned retry_budget = retry_env     ? static_cast<unsigned>(std::strtoul(retry_env, nullptr, 10))
                                  : edge.keys ? interior_retry_budget(budget)
                                              : budget;
    // The edge's site list and its own retry and undecided lists, and their counts in
    // counters[9..11]: its sites, its retries, its undecided.
    DeviceArray<int> d_edge(edge_depth > 0 ? 3 * n : 0, stream);
    int* const edge_sites = d_edge.get();
    int* const edge_retry = edge_depth > 0 ? edge_sites + n : nullptr;
    int* const edge_undecided = edge_depth > 0 ? edge_sites + 2 * n : nullptr;
    unsigned int* const edge_counts = d_counters.get() + 9;
    // For comparisons: EXPANSE_CUDA_EDGE_FIRST_BUDGET sets the edge's first pass's budget apart;
    // EXPANSE_CUDA_EDGE_AFTER=phase0 starts the edge's stream after the first phase, which shows
    // what the edge's walks cost the first phase beside them (session 24 call 1, 4096^2: uniform's
    // first phase 22.72 -> 20.31 ms, kuzmin's 39.47 -> 36.15, though the edge then ends last).
    // The edge's kernels in blocks of one or two warps instead of four, so that a finished warp
    // frees its slot, did not move it (call 2).
    const char* edge_first_env = std::getenv("EXPANSE_CUDA_EDGE_FIRST_BUDGET");
    const unsigned edge_budget =
        edge_first_env ? std::min(budget, static_cast<unsigned>(std::strtoul(edge_first_env, nullptr, 10))) : pass_budget;
    // The edge's retry (the warps that walk again the edge's sites that ran past the first pass's
    // budget) on a stream of the main stream's priority, 2 blocks a multiprocessor, rather than
    // on the edge's stream of the highest: its blocks then wait for the first phase's to be
    // dispatched and run in that phase's drain and beside the second phase, where on the edge's
    // stream they took their slots from the first phase (H100, session 30 calls 4-5, GPU-only,
    // two rounds alternated: 4096^2 uniform 34.18 / 34.22 -> 33.90 / 33.91 ms, its first phase
    // ending at 21.1 ms instead of 21.6; kuzmin 52.46 / 52.51 -> 51.97 / 51.93; gaussian 41.0
    // either way; 2048^2 kuzmin 16.95 -> 16.73, 1024^2 6.86 -> 6.15). The edge's first pass
    // stays on its stream: at the main stream's priority it waited out the first phase and
    // ended last (call 3: uniform 34.2 -> 35.1-35.5). Lattices keep the former launch: no size
    // gained (calls 5-7). EXPANSE_CUDA_EDGE_RETRY=edge launches it as before, =low:B with B
    // blocks a multiprocessor, for comparisons.
    const char* edge_retry_env = std::getenv("EXPANSE_CUDA_EDGE_RETRY");
    const bool edge_retry_low =
        ctx.low_stream && !exact_lattice && !(edge_retry_env && std::strcmp(edge_retry_env, "edge") == 0);
    const int edge_retry_blocks =
        !edge_retry_low ? retry_blocks
        : edge_retry_env && std::strncmp(edge_retry_env, "low:", 4) == 0
            ? std::max(1, std::atoi(edge_retry_env + 4)) * ctx.multiprocessors
            : 2 * ctx.multiprocessors;
    const char* edge_after_env = std::getenv("EXPANSE_CUDA_EDGE_AFTER");
    const bool edge_after_phase0 = edge_after_env && std::strcmp(edge_after_env, "phase0") == 0;
    const bool light = two_passes && !first_full;
    // The stars are walked in two phases (StarInbox) above 2^18 sites, else in one; or as
    // EXPANSE_CUDA_PHASES (1 or 2) says. Morton order (EXPANSE_CUDA_ORDER) walks in one. H100,
    // GPU-only, alternated with one phase (session 15 call 3): 4096^2 uniform 49.2 -> 41.9 ms
    // (star kernels 40.8 -> 33.5), kuzmin 89.1 -> 75.0, gaussian 70.4 -> 59.1, grid 27.5 ->
    // 25.0; 1024^2 -4% to -9%. At 512^2, half a wave of blocks a phase, kuzmin lost 4% (4.8 ->
    // 5.0 ms) while uniform, gaussian and grid were no slower.
    // On quantile cells the phases' blocks start from both ends of the cell order
    // (ends_first_block): its first and last rows hold the far tails in y, whose sites walk longest
    // (counted on the CPU, kuzmin 4096^2: the first and last twentieth of the blocks cost twice
    // the others), and in order the last of them made the kernel's tail (ncu, call 2: kuzmin's first
    // phase kept its multiprocessors active 93% of its cycles, uniform's 99.7%). H100, GPU-only,
    // two rounds against the cell order (session 18 call 4): gaussian 4096^2 49.98 / 50.55 ->
    // 48.63 / 49.26 ms, kuzmin 4096^2 69.46 / 69.52 -> 68.14 / 69.45 (its first phase 40.7 -> 39.0,
    // the edge's stream then later), kuzmin 2048^2 23.45 / 23.52 -> 23.05 / 22.61; uniform inputs
    // unchanged (4096^2 40.51 / 40.53 -> 40.60 / 40.62), so uniform cells keep the order.
    // EXPANSE_CUDA_BLOCK_ORDER=cells or =ends forces one.
    const char* block_order_env = std::getenv("EXPANSE_CUDA_BLOCK_ORDER");
    const bool ends_first = block_order_env ? std::strcmp(block_order_env, "ends") == 0 : !buckets.uniform();
    const char* phases_env = std::getenv("EXPANSE_CUDA_PHASES");
    const bool two = phases_env ? std::atoi(phases_env) == 2 : n > (std::size_t{1} << 18);
    const int phases = two && !order ? 2 : 1;
    // The first phase's sites that run past its budget are walked again (by warps) on the edge's
    // stream during the second phase, which needs nothing from them: their stars post nothing
    // (no walk posts after the first phase), and the second phase searches for what they would
    // have posted, as before. At the end the main stream's retry walks only the second phase's
    // and the undecided walks' sites; it was the stage's tail. H100, 4096^2, session 26 calls 1
    // and 7: the tail after the second phase 2.6 -> 1.5 ms (kuzmin, 5,740 sites) and 1.6 -> 0.9
    // (gaussian, 56), GPU-only kuzmin 59.7 -> 59.1-59.4 ms, gaussian 44.4-44.5 -> 43.8, gaussian
    // 2048^2 15.4 -> 14.1; kuzmin 2048^2 0.3 ms slower, uniform inputs (no retries) unchanged.
    // Session 19 (call 6) had tried a third stream and lost on kuzmin.
    // EXPANSE_CUDA_EARLY_RETRY=0 keeps every retry at the end, for comparisons.
    const char* early_retry_env = std::getenv("EXPANSE_CUDA_EARLY_RETRY");
    const bool early_retry = edge.keys && phases == 2 && two_passes &&
                             !(early_retry_env && std::strcmp(early_retry_env, "0") == 0);
    const std::size_t inboxes = phases == 2 ? n / 2 + 1 : 0;
    DeviceArray<int> d_inbox_slots(inboxes * kInboxWords, stream);
    DeviceArray<std::uint32_t> d_inbox_counts(inboxes, stream);
    if (inboxes > 0) EXPANSE_CUDA(cudaMemsetAsync(d_inbox_counts.get(), 0, d_inbox_counts.bytes(), stream));
    // The second phase records the stars that its sites' inboxes hold whole before it walks the
    // others (inbox_star_kernel). H100, GPU-only, two rounds against every odd site walked
    // (session 22 call 8): 4096^2 uniform 37.66 -> 36.27 ms, gaussian 48.14 -> 46.52, kuzmin
    // 69.44 -> 67.13; at 1024^2 and 2048^2 (uniform, lattice) and on the 4096^2 lattice within
    // noise either way (call 9). EXPANSE_CUDA_INBOX_FIRST=0 walks every odd site, for comparisons.
    const char* inbox_first_env = std::getenv("EXPANSE_CUDA_INBOX_FIRST");
    const bool inbox_first = phases == 2 && !(inbox_first_env && std::strcmp(inbox_first_env, "0") == 0);
    // Its list of the sites that search lives in the triangle offsets' room (offset[1..n], written
    // only by the scan after the stars): an array of its own, 32 MB at 4096^2, took the bucket
    // stage of the next triangulation from 0.92 to 2.0 ms on uniform cells (H200, session 22
    // calls 1-2, whatever the kernels; why was not found, the pool's placement of the bucketing's
    // arrays most likely).
    int* const d_search = d_offset.get() + 1;
    // with_strips: the edge's walks and the warps' second pass compiled with the strips' scans
    // (walk_star_boxes' Strips), where strips are built; else without (their code alone, unused,
    // slowed kuzmin's edge stream: session 24 call 4).
    auto walk_passes = [&](auto first_blocks, auto later_blocks, auto edge_blocks, auto lattice, auto with_strips) {
      constexpr int first_b = decltype(first_blocks)::value;
      constexpr int later_b = decltype(later_blocks)::value;
      constexpr int edge_b = decltype(edge_blocks)::value;
      constexpr bool exact = decltype(lattice)::value;
      constexpr bool striped = decltype(with_strips)::value;
      // edge_passed: set where the edge's retry went to ctx.low_stream.
      cudaEvent_t fork = nullptr, join = nullptr, stripped = nullptr, phase0_done = nullptr, edge_passed = nullptr;
      timeline.mark("start", stream);
      // The strips serve the edge's walks and the warps' second pass: built on the edge's stream,
      // beside the first phase, which needs none (session 24 call 3: 0.22 ms of the bucket
      // stage at 4096^2 uniform, on the main stream), or here without an edge stream.
      if (strip_walks && !edge.keys) strips.build(g, stream);
      auto launch_edge = [&] {
        if (!edge.keys) return;
        edge_list_kernel<<<blocks_for(n), kThreads, 0, stream>>>(edge, static_cast<int>(n), edge_sites, edge_counts);
        EXPANSE_CUDA(cudaEventCreateWithFlags(&fork, cudaEventDisableTiming));
        EXPANSE_CUDA(cudaEventCreateWithFlags(&join, cudaEventDisableTiming));
        EXPANSE_CUDA(cudaEventRecord(fork, stream));
        EXPANSE_CUDA(cudaStreamWaitEvent(ctx.edge_stream, fork));
        const cudaStream_t es = ctx.edge_stream;
        if (strip_walks) {
          strips.build(g, es);
          EXPANSE_CUDA(cudaEventCreateWithFlags(&stripped, cudaEventDisableTiming));
          EXPANSE_CUDA(cudaEventRecord(stripped, es));
        }
        if (light) {
          star_list_kernel<StarSearch::boxes, edge_b, exact, true, false, striped><<<retry_blocks, 128, 0, es>>>(
              g, d_pred.get(), d_star.get(), d_info.get(), d_owned.get(), d_counters.get(), edge_budget, edge_sites,
              edge_counts, edge_retry, edge_undecided, edge_counts + 1);
          star_list_kernel<StarSearch::boxes, edge_b, exact, false, false, striped><<<retry_blocks, 128, 0, es>>>(
              g, d_pred.get(), d_star.get(), d_info.get(), d_owned.get(), d_counters.get(), edge_budget,
              edge_undecided, edge_counts + 2, edge_retry, nullptr, edge_counts + 1);
        } else {
          star_list_kernel<StarSearch::boxes, edge_b, exact, false, false, striped><<<retry_blocks, 128, 0, es>>>(
              g, d_pred.get(), d_star.get(), d_info.get(), d_owned.get(), d_counters.get(), edge_budget, edge_sites,
              edge_counts, edge_retry, nullptr, edge_counts + 1);
        }
        timeline.mark("edge first pass", es);
        const cudaStream_t rs = edge_retry_low ? ctx.low_stream : es;
        if (edge_retry_low) {
          EXPANSE_CUDA(cudaEventCreateWithFlags(&edge_passed, cudaEventDisableTiming));
          EXPANSE_CUDA(cudaEventRecord(edge_passed, es));
          EXPANSE_CUDA(cudaStreamWaitEvent(rs, edge_passed));
        }
        star_retry_kernel<StarSearch::boxes, edge_b, exact, striped><<<edge_retry_blocks, 128, 0, rs>>>(
            g, d_pred.get(), d_star.get(), d_info.get(), d_owned.get(), d_counters.get(), budget, edge_retry,
            edge_counts + 1);
        timeline.mark("edge retry", rs);
      };
      // The first phase's retries on the edge's stream, once its own walks are done, beside the
      // second phase: the list as the first phase leaves it (its length kept in counters[13]);
      // the main stream's retry takes what the second phase and the undecided walks add.
      auto launch_first_phase_retry = [&] {
        if (!early_retry) return;
        copy_count_kernel<<<1, 1, 0, stream>>>(d_counters.get() + 7, d_counters.get() + 13);
        EXPANSE_CUDA(cudaEventCreateWithFlags(&phase0_done, cudaEventDisableTiming));
        EXPANSE_CUDA(cudaEventRecord(phase0_done, stream));
        EXPANSE_CUDA(cudaStreamWaitEvent(ctx.edge_stream, phase0_done));
        star_retry_kernel<StarSearch::boxes, first_b, exact, striped><<<retry_blocks, 128, 0, ctx.edge_stream>>>(
            g, d_pred.get(), d_star.get(), d_info.get(), d_owned.get(), d_counters.get(), retry_budget, d_retry.get(),
            d_counters.get() + 13);
        timeline.mark("phase 0 retry", ctx.edge_stream);
      };
      if (!edge_after_phase0) launch_edge();
      // The phases' kernels, one after the other (StarInbox): the first posts, the second reads.
      // The second phase either walks every odd site, or first records those whose inboxes hold
      // their whole stars (inbox_star_kernel) and walks the rest from a list (`later_list`).
      auto walk_phases = [&](auto first, auto later, auto later_list, int* undecided) {
        for (int phase = 0; phase < phases; ++phase) {
          const StarInbox inbox{d_inbox_slots.get(), d_inbox_counts.get(), phase == 1};
          const std::size_t sites = (n - std::min<std::size_t>(n, phase) + phases - 1) / phases;
          if (sites == 0) continue;
          if (phase > 0 && inbox_first) {
            inbox_star_kernel<<<blocks_for(sites, kInboxThreads), kInboxThreads, 0, stream>>>(
                d_pred.get(), static_cast<int>(n), d_star.get(), d_info.get(), d_owned.get(), edge, inbox,
                d_search, d_counters.get() + 12, ends_first);
            timeline.mark("phase 1 from inboxes", stream);
            later_list<<<blocks_for(sites, 128), 128, 0, stream>>>(
                g, d_pred.get(), d_star.get(), d_info.get(), d_owned.get(), d_counters.get(), pass_budget,
                d_search, d_counters.get() + 12, d_retry.get(), undecided, d_counters.get() + 7, pass, inbox);
          } else {
            (phase > 0 ? later : first)<<<blocks_for(sites, 128), 128, 0, stream>>>(
                g, d_pred.get(), static_cast<int>(n), d_star.get(), d_info.get(), d_owned.get(), d_counters.get(),
                pass_budget, order, pass, d_retry.get(), undecided, edge, phases, phase, inbox, ends_first);
          }
          timeline.mark(phase == 0 ? "phase 0" : "phase 1", stream);
          if (phase == 0 && edge_after_phase0) launch_edge();
          if (phase == 0) launch_first_phase_retry();
        }
      };
      // A light first pass (no exact path, no row clipping) hands its hard sites on to the second.
      if (light) {
        walk_phases(star_kernel<StarSearch::boxes, first_b, exact, true>,
                    star_kernel<StarSearch::boxes, later_b, exact, true, true>,
                    star_list_kernel<StarSearch::boxes, later_b, exact, true, true>, d_undecided.get());
        star_list_kernel<StarSearch::boxes, first_b, exact><<<retry_blocks, 128, 0, stream>>>(
            g, d_pred.get(), d_star.get(), d_info.get(), d_owned.get(), d_counters.get(), pass_budget,
            d_undecided.get(), d_counters.get() + 8, d_retry.get(), nullptr, d_counters.get() + 7);
        timeline.mark("undecided", stream);
      } else {
        walk_phases(star_kernel<StarSearch::boxes, first_b, exact>,
                    star_kernel<StarSearch::boxes, later_b, exact, false, true>,
                    star_list_kernel<StarSearch::boxes, later_b, exact, false, true>, nullptr);
      }
      if (stripped) EXPANSE_CUDA(cudaStreamWaitEvent(stream, stripped));
      if (two_passes)
        star_retry_kernel<StarSearch::boxes, first_b, exact, striped><<<retry_blocks, 128, 0, stream>>>(
            g, d_pred.get(), d_star.get(), d_info.get(), d_owned.get(), d_counters.get(), retry_budget,
            d_retry.get(), d_counters.get() + 7, early_retry ? d_counters.get() + 13 : nullptr);
      timeline.mark("retry", stream);
      if (edge.keys) {
        EXPANSE_CUDA(cudaEventRecord(join, ctx.edge_stream));
        EXPANSE_CUDA(cudaStreamWaitEvent(stream, join));
        if (edge_passed) {
          // The same event, re-recorded after the retry: the main stream waits for it too.
          EXPANSE_CUDA(cudaEventRecord(edge_passed, ctx.low_stream));
          EXPANSE_CUDA(cudaStreamWaitEvent(stream, edge_passed));
          EXPANSE_CUDA(cudaEventDestroy(edge_passed));
        }
        EXPANSE_CUDA(cudaEventDestroy(fork));
        EXPANSE_CUDA(cudaEventDestroy(join));
      }
      if (stripped) EXPANSE_CUDA(cudaEventDestroy(stripped));
      if (phase0_done) EXPANSE_CUDA(cudaEventDestroy(phase0_done));
    };
    // Lattices are integer inputs, which run at 6 blocks a multiprocessor.
    constexpr std::integral_constant<int, 6> six{};
    if (exact_lattice)
      walk_passes(six, six, six, std::true_type{}, std::false_type{});  // lattices take no strips
    else
      with_star_blocks(star_blocks.first, [&](auto first) {
        with_star_blocks(star_blocks.later, [&](auto later) {
          with_star_blocks(star_blocks.edge, [&](auto edge_b) {
            if (strip_walks)
              walk_passes(first, later, edge_b, std::false_type{}, std::true_type{});
            else
              walk_passes(first, later, edge_b, std::false_type{}, std::false_type{});
          });
        });
      });
  }
  EXPANSE_CUDA(cudaGetLastError());
  timer.end();

  timer.begin("scan");
  std::size_t temp_bytes = d_temp.bytes();
  EXPANSE_CUDA(cub::DeviceScan::InclusiveSum(d_temp.get(), temp_bytes, d_owned.get(), d_offset.get() + 1,
                                             static_cast<int>(n), stream));
  timer.end();

  // The one synchronisation before the output: its size. The words go to pinned memory, so the
  // copies stay asynchronous and the host readies the output while the device works.
  // triangles, then counter words 0..6: [0] deferred, [2..3] predicates (u64), [4] max work per
  // site, [5] sites over 4096 work units, [6] sites deferred by the work budget.
  unsigned int* const words = ctx.pinned_words;
  EXPANSE_CUDA(cudaMemcpyAsync(&words[0], d_offset.get() + n, sizeof(int), cudaMemcpyDeviceToHost, stream));
  EXPANSE_CUDA(cudaMemcpyAsync(&words[1], d_counters.get(), 7 * sizeof(unsigned int), cudaMemcpyDeviceToHost, stream));

  // The triangles, written where the scan put them into room for the whole triangulation (the
  // most the device can make), so that the device goes on while the host readies the output
  // below: sized to the count, they waited for the host to read it (H100, 4096^2 uniform: the
  // emit's 10 ms after the host's 108 ms of output allocation, session 6 call 10).
  const std::size_t full = n >= 3 ? 2 * n - input.hull.sites.size() - 2 : 0;
  const bool with_neighbors = true;
  DeviceArray<int> d_triangles(3 * full, stream);
  DeviceArray<int> d_neighbors(with_neighbors ? 3 * full : 0, stream);
  // EXPANSE_CUDA_EMIT=search finds every neighbour in its owner's star (for comparisons).
  const char* emit_env = std::getenv("EXPANSE_CUDA_EMIT");
  const bool known_places = !(emit_env && std::strcmp(emit_env, "search") == 0);
  timer.begin("emit");
  // The owned counts are scanned: their array takes each site's owned bitmask now.
  std::uint32_t* const d_owned_mask = reinterpret_cast<std::uint32_t*>(d_owned.get());
  emit_triangles_kernel<<<blocks_for(n, kEmitSites), kEmitSites, 0, stream>>>(
      d_star.get(), d_info.get(), d_offset.get(), d_sorted_ids, static_cast<int>(n), static_cast<int>(full),
      d_triangles.get(), d_owned_mask);
  if (with_neighbors && full > 0)
    emit_neighbors_kernel<<<blocks_for(full, 128), 128, 0, stream>>>(
        d_star.get(), d_info.get(), d_offset.get(), d_owned_mask, d_triangles.get(), d_rank.get(),
        static_cast<int>(n), static_cast<int>(full), d_neighbors.get(), known_places);
  EXPANSE_CUDA(cudaGetLastError());
  timer.end();

  // Room for the whole triangulation (2n - h - 2), which is also the most the device can make:
  // the seam stage appends what deferred sites leave in place, where exactly-sized vectors would
  // have to move (805 MB at 4096^2) first. Fresh pages are faulted in on every core and zeroed
  // while the star kernel runs: done after it, this took ~460 ms at 4096^2 on the H100's host.
  const auto host_launched = Clock::now();
  auto& partial = result.partial;
  allocate_full_triangulation(partial, n, input.hull.sites.size(), input.recycled);
  const auto host_allocated = Clock::now();
  // EXPANSE_CUDA_PIN_OUTPUT=1 pins the output in place while the device still works, so that
  // the download runs at the bus's speed; its pages are released on another thread while the
  // seam and output stages run (GrowResult::background). Off by default: on the H100's host at
  // 4096^2 (session 8 call 2, alternated in one call) the download fell from 26.5 to 15.0 ms
  // and the release hid, but pinning's 27 ms of kernel work slowed the sites' concurrent copy
  // to the host from 55-59 to 83-86 ms, and host to host went from 169-177 to 175-190 ms.
  auto pinned = std::make_unique<PinnedInPlace>();
  {
    const char* forced = std::getenv("EXPANSE_CUDA_PIN_OUTPUT");
    if (forced && *forced && std::strcmp(forced, "0") != 0) {
      pinned->pin(partial.triangles.data(), partial.triangles.capacity() * sizeof(partial.triangles[0]));
      if (with_neighbors)
        pinned->pin(partial.neighbors.data(), partial.neighbors.capacity() * sizeof(partial.neighbors[0]));
    }
  }
  const auto host_pinned = Clock::now();

  EXPANSE_CUDA(cudaStreamSynchronize(stream));
  unsigned int sizes[8];
  std::memcpy(sizes, words, sizeof sizes);
  const std::size_t triangle_count = sizes[0];
  if (triangle_count > full)
    throw Error(ErrorCode::device_error, "CUDA backend: the stars made " + std::to_string(triangle_count) +
                                             " triangles, more than a triangulation of " + std::to_string(n) +
                                             " sites has (" + std::to_string(full) + ")");
  const std::size_t triangle_bytes = 3 * triangle_count * sizeof(int);
  // The audit, on the device. Open edges inside the hull (left by deferred sites) are rare:
  // listed as the audit finds them, then sorted and matched against their reverses.
  bool audited = false;
  std::size_t open_pairs_linked = 0, open_edges = 0;
  if (with_neighbors && triangle_count > 0) {
    timer.begin("audit");
    // Counts into d_counters[0..1] and lists up to `room` open edges (d_counters[2] counting).
    auto audit = [&](std::uint64_t* open_keys, int* open_slots, std::size_t room) {
      audit_kernel<<<blocks_for(triangle_count), kThreads, 0, stream>>>(
          d_triangles.get(), d_neighbors.get(), static_cast<int>(triangle_count), d_rank.get(), d_pred.get(),
          d_counters.get(), open_keys, open_slots, static_cast<unsigned>(room));
      EXPANSE_CUDA(cudaGetLastError());
    };
    // Room for the open edges of a few thousand deferred sites (at 4096^2: 93 uniform, 41 kuzmin);
    // more are listed by a second audit, with room for all. EXPANSE_CUDA_AUDIT_ROOM sets the
    // room (tests take the second audit's path with it).
    const char* room_env = std::getenv("EXPANSE_CUDA_AUDIT_ROOM");
    const std::size_t room = std::min<std::size_t>(
        3 * triangle_count, room_env ? std::strtoul(room_env, nullptr, 10) : std::size_t{1} << 18);
    DeviceArray<std::uint64_t> d_open(room, stream), d_open_sorted(room, stream);
    DeviceArray<int> d_slots(room, stream), d_slots_sorted(room, stream);
    EXPANSE_CUDA(cudaMemsetAsync(d_counters.get(), 0, 4 * sizeof(unsigned int), stream));
    audit(d_open.get(), d_slots.get(), room);
    EXPANSE_CUDA(cudaMemcpyAsync(&words[8], d_counters.get(), 2 * sizeof(unsigned int), cudaMemcpyDeviceToHost,
                                 stream));
    EXPANSE_CUDA(cudaStreamSynchronize(stream));
    const unsigned bad = words[8], open = words[9];
    open_edges = open;
    audited = bad == 0 && open == 0;
    if (bad == 0 && open > 0) {
      // Open edges inside the hull: listed with where they are, sorted, and the pairs linked.
      std::uint64_t *keys = d_open.get(), *keys_sorted = d_open_sorted.get();
      int *slots = d_slots.get(), *slots_sorted = d_slots_sorted.get();
      std::optional<DeviceArray<std::uint64_t>> all_keys, all_keys_sorted;
      std::optional<DeviceArray<int>> all_slots, all_slots_sorted;
      if (open > room) {
        keys = all_keys.emplace(open, stream).get();
        keys_sorted = all_keys_sorted.emplace(open, stream).get();
        slots = all_slots.emplace(open, stream).get();
        slots_sorted = all_slots_sorted.emplace(open, stream).get();
        EXPANSE_CUDA(cudaMemsetAsync(d_counters.get(), 0, 4 * sizeof(unsigned int), stream));
        audit(keys, slots, open);
      }
      std::size_t bytes = 0;
      EXPANSE_CUDA(cub::DeviceRadixSort::SortPairs(nullptr, bytes, keys, keys_sorted, slots, slots_sorted,
                                                   static_cast<int>(open), 0, 64, stream));
      DeviceArray<unsigned char> d_sort_temp(bytes, stream);
      EXPANSE_CUDA(cub::DeviceRadixSort::SortPairs(d_sort_temp.get(), bytes, keys, keys_sorted, slots, slots_sorted,
                                                   static_cast<int>(open), 0, 64, stream));
      // What stays open (no reverse) is listed for the seam stage, which would otherwise read
      // all the links to find it: into `slots`, free again.
      EXPANSE_CUDA(cudaMemsetAsync(d_counters.get(), 0, 4 * sizeof(unsigned int), stream));
      link_open_pairs_kernel<<<blocks_for(open), kThreads, 0, stream>>>(keys_sorted, slots_sorted, open,
                                                                       d_neighbors.get(), d_counters.get(), slots);
      EXPANSE_CUDA(cudaGetLastError());
      EXPANSE_CUDA(cudaMemcpyAsync(&words[10], d_counters.get(), 4 * sizeof(unsigned int), cudaMemcpyDeviceToHost,
                                   stream));
      EXPANSE_CUDA(cudaStreamSynchronize(stream));
      const unsigned duplicates = words[10], open_after = words[12], linked = words[13];
      audited = duplicates == 0 && open_after + linked == open;
      open_pairs_linked = linked / 2;
      if (audited) {
        std::vector<int> still_open(open_after);
        EXPANSE_CUDA(cudaMemcpyAsync(still_open.data(), slots, open_after * sizeof(int), cudaMemcpyDeviceToHost,
                                     stream));
        EXPANSE_CUDA(cudaStreamSynchronize(stream));
        std::sort(still_open.begin(), still_open.end());  // in the atomics' order; the seam's is the triangles'
        partial.open_slots.emplace(still_open.begin(), still_open.end());
      }
    } else if (audited) {
      partial.open_slots.emplace();  // nothing open
    }
    timer.end();
  }

  const auto host_emit = Clock::now();
  partial.triangles.resize(triangle_count);  // shrinks: no reallocation
  partial.neighbors.resize(with_neighbors ? triangle_count : 0);
  timer.begin("download");
  const auto download = [&](void* host, const void* device) {
    if (pinned->pinned(host)) {
      EXPANSE_CUDA(cudaMemcpyAsync(host, device, triangle_bytes, cudaMemcpyDeviceToHost, stream));
    } else {
      ctx.staging->download(host, device, triangle_bytes, stream);
    }
  };
  download(partial.triangles.data(), d_triangles.get());
  if (with_neighbors) download(partial.neighbors.data(), d_neighbors.get());
  timer.end();
  EXPANSE_CUDA(cudaStreamSynchronize(stream));
  const auto host_done = Clock::now();
  if (!pinned->empty())
    result.background = std::async(std::launch::async, [release = std::move(pinned)]() mutable { release.reset(); });

  partial.deferred_expansions = sizes[1];
  // The device ran the host audit's checks: a failure there is final (the host would find the
  // same, at ~300 ms for 4096^2 kuzmin), and the pipeline derives the adjacency instead. Edges
  // open from both sides (both ends deferred) were linked above: before, they failed the audit
  // and kuzmin 4096^2 spent ~600 ms deriving adjacency on the host for 195 deferred sites.
  if (with_neighbors && triangle_count > 0 && !audited) partial.neighbors.clear();
  result.adjacency_audited = audited;
  RunCounters& counters = last_run_counters();
  counters = {};
  counters.open_pairs_linked = open_pairs_linked;
  counters.open_edges = open_edges;
  std::uint64_t predicates = 0;
  std::memcpy(&predicates, &sizes[3], sizeof predicates);
  counters.predicates = predicates;
  counters.bytes_to_device = on_device ? 0 : n * sizeof(double2) + d_uploaded_hull.bytes();
  counters.bytes_to_host = (with_neighbors ? 2 : 1) * triangle_bytes + 2 * sizeof(int);
  counters.triangles = triangle_count;
  counters.max_cells_per_site = sizes[5];
  counters.sites_over_4096_cells = sizes[6];
  counters.sites_over_budget = sizes[7];
  counters.uniform_cells = buckets.uniform();
  result.iterations = 1;
  result.device_stages = timer.collect();
  timeline.print("star stage timeline (ms)");
  if (timeline.on()) {
    // The lists' lengths beside the timeline (counters[7..12]).
    unsigned int c[13];
    EXPANSE_CUDA(cudaMemcpy(c, d_counters.get(), sizeof c, cudaMemcpyDeviceToHost));
    std::fprintf(stderr, "star stage lists: retry %u; undecided %u; edge %u; edge retry %u; edge undecided %u; phase 1 search %u\n",
                 c[7], c[8], c[9], c[10], c[11], c[12]);
  }
  auto ms = [](auto a, auto b) { return std::chrono::duration<double, std::milli>(b - a).count(); };
  result.host_stages.push_back({"cuda upload (host)", ms(host_start, host_uploaded)});
  result.host_stages.push_back({"cuda output allocation (host, while the device works)", ms(host_launched, host_allocated)});
  result.host_stages.push_back({"cuda output pinning (host, while the device works)", ms(host_allocated, host_pinned)});
  result.host_stages.push_back({"cuda device work (host wait)", ms(host_uploaded, host_emit) - ms(host_launched, host_pinned)});
  result.host_stages.push_back({"cuda download (host)", ms(host_emit, host_done)});
}

}  // namespace expanse::detail::cuda
