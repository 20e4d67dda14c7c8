#pragma once
// Copies of the bucketed sites that some walks scan instead of box rows: the grid's boundary
// strips (BoundaryStrips: its outer columns and rows, sorted by distance inwards) and the outer
// columns of quantile cells, column after column (TailColumns). Both live in memory the bucketing
// no longer needs. Included by star_kernels.cu alone.
#include <cub/block/block_scan.cuh>
#include <cub/device/device_scan.cuh>
#include <cub/device/device_segmented_radix_sort.cuh>

#include <cstdint>

#include "cuda_internal.hpp"
#include "device_geometry.cuh"

namespace expanse::detail::cuda {
namespace {

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
/// moved the bucketing of clustered inputs by a millisecond (kuzmin 4096^2 1.6 -> 2.7 ms, H100),
/// the pool placing its arrays elsewhere.
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

}  // namespace
}  // namespace expanse::detail::cuda
