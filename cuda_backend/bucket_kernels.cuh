#pragma once
// Kernels that bucket sites by cell of the per-site layout's grid (star_kernels.cu): the grid's
// quantile boundaries from a sample, a stable sort by cell, each cell's first position.
#include <cub/device/device_radix_sort.cuh>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <cstring>

#include "cuda_internal.hpp"
#include "device_geometry.cuh"
#include "sorted_order_kernels.cuh"
#include "star_grid.hpp"

namespace expanse::detail::cuda {
namespace {

/// keys[i]: point i's cell, and with kSubCellBits (`within`) below it where in its cell's
/// width it lies (the sites of a cell then walked in x order).
constexpr int kSubCellBits = 8;
__global__ void cell_keys_kernel(GridView g, const double2* points, int n, std::uint32_t* keys, int* ids,
                                 bool within = false) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= n) return;
  const double2 p = points[i];
  const int cx = g.cell_x(p.x);
  std::uint32_t key = static_cast<std::uint32_t>(g.cell_y(p.y) * g.gx + cx);
  if (within) {
    // Any monotone guess will do: the order within a cell is free.
    double lo, hi;
    g.x_bounds(cx, &lo, &hi);
    const double t = (p.x - lo) / (hi - lo) * (1 << kSubCellBits);
    const std::uint32_t part =
        t > 0.0 ? (t < (1 << kSubCellBits) ? static_cast<std::uint32_t>(t) : (1u << kSubCellBits) - 1u) : 0u;
    key = (key << kSubCellBits) | part;
  }
  keys[i] = key;
  ids[i] = i;
}

/// keys[i] >>= shift: the cells alone again, for the cell starts and EdgeCells.
__global__ void cells_of_keys_kernel(std::uint32_t* keys, int n, int shift) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i < n) keys[i] >>= shift;
}

__global__ void hull_predecessor_kernel(const int* hull, int h, const int* rank, int* pred) {
  const int t = blockIdx.x * blockDim.x + threadIdx.x;
  if (t >= h) return;
  pred[rank[hull[t]]] = rank[hull[t == 0 ? h - 1 : t - 1]];
}

/// Quantile grid: a pseudo-random sample of the coordinates (a hashed index, so that ordered
/// inputs such as row-major grids do not alias).
__global__ void sample_kernel(const double2* points, int n, int samples, double* xs, double* ys) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= samples) return;
  const double2 p = points[quantile_sample_site(i, n, samples)];
  xs[i] = p.x;
  ys[i] = p.y;
}

/// The sample's evenness histogram (star_grid.hpp) into `bins` (zeroed before): each block
/// counts its slice in shared memory, then adds its counts.
__global__ void evenness_count_kernel(EvennessFrame f, const double* xs, const double* ys, int samples,
                                      unsigned int* bins) {
  __shared__ unsigned int local[kEvennessBins * kEvennessBins];
  for (int b = threadIdx.x; b < kEvennessBins * kEvennessBins; b += blockDim.x) local[b] = 0;
  __syncthreads();
  for (int i = blockIdx.x * blockDim.x + threadIdx.x; i < samples; i += gridDim.x * blockDim.x)
    atomicAdd(&local[evenness_bin(f, xs[i], ys[i])], 1u);
  __syncthreads();
  for (int b = threadIdx.x; b < kEvennessBins * kEvennessBins; b += blockDim.x)
    if (local[b]) atomicAdd(&bins[b], local[b]);
}

/// *max_count = the fullest of the histogram's bins (one block of kEvennessBins^2 threads).
__global__ void __launch_bounds__(kEvennessBins * kEvennessBins) evenness_max_kernel(const unsigned int* bins,
                                                                                    unsigned int* max_count) {
  __shared__ unsigned int fullest;
  if (threadIdx.x == 0) fullest = 0;
  __syncthreads();
  atomicMax(&fullest, bins[threadIdx.x]);
  __syncthreads();
  if (threadIdx.x == 0) *max_count = fullest;
}

/// bounds[j] = the (j / cells)-quantile of the sorted sample, j = 1 .. cells - 1, its tails weighed
/// where quantile_tails finds them heavy.
/// With `heavy`, also whether the axis' tails are heavy (weighed: quantile_tails), as 1 or 0.
__global__ void quantile_kernel(const double* sorted, int samples, int cells, TailWeighing weighing, double* bounds,
                                unsigned int* heavy = nullptr) {
  const int j = blockIdx.x * blockDim.x + threadIdx.x;
  if (j > cells) return;
  const QuantileTails tails = quantile_tails(sorted, samples, weighing);
  if (heavy && j == 0) *heavy = tails.tail > 0 ? 1u : 0u;
  bounds[j] = (j == 0 || j == cells) ? 0.0 /* never read */ : quantile_boundary(sorted, samples, cells, j, tails);
}

/// A quantile axis for its guide (quantile_guide.hpp): bounds[1 .. cells) are its
/// boundaries; `logarithmic` and `even` take the two keys' tables (quantile_guide_capacity
/// entries each).
struct GuideAxis {
  const double* bounds;
  int cells;
  double lo, hi;
  int* logarithmic;
  int* even;

  EXPANSE_DEVICE_FORCE QuantileGuideKey key(int logarithmic_key) const {
    return logarithmic_key ? plan_logarithmic_quantile_guide(bounds + 1, cells, lo, hi)
                           : plan_even_quantile_guide(lo, hi, cells);
  }
};

/// Both axes' guides' tables, a thread an entry (blockIdx.y: the axis; blockIdx.z: 0 the
/// logarithmic key, 1 the even one), and each table's cost summed into costs[2 * axis + z]
/// (zeroed before; build_quantile_guide on the device). In one block an axis, the two axes one
/// after the other, the tables took 0.18 ms of kuzmin's bucketing at 4096^2 (H100, ncu): each entry is a binary search over the boundaries.
constexpr int kGuideThreads = 256;
__global__ void __launch_bounds__(kGuideThreads) guide_tables_kernel(GuideAxis x, GuideAxis y,
                                                                     unsigned long long* costs) {
  __shared__ unsigned long long block_cost;
  const GuideAxis& axis = blockIdx.y == 0 ? x : y;
  const QuantileGuideKey key = axis.key(blockIdx.z == 0);
  int* const table = blockIdx.z == 0 ? axis.logarithmic : axis.even;
  const int k = static_cast<int>(blockIdx.x * blockDim.x + threadIdx.x);
  if (threadIdx.x == 0) block_cost = 0;
  __syncthreads();
  if (k <= 2 * key.half) {
    const int first = quantile_guide_entry(axis.bounds + 1, axis.cells - 1, key, k);
    table[k] = first;
    if (k < 2 * key.half) {
      const long long cost =
          quantile_guide_columns_cost(quantile_guide_entry(axis.bounds + 1, axis.cells - 1, key, k + 1) - first);
      if (cost > 0) atomicAdd(&block_cost, static_cast<unsigned long long>(cost));
    }
  }
  __syncthreads();
  if (threadIdx.x == 0 && block_cost > 0) atomicAdd(costs + 2 * blockIdx.y + blockIdx.z, block_cost);
}

/// chosen[a]: axis a's cheaper key (the logarithmic one where the costs tie), as
/// build_quantile_guide chooses.
__global__ void guide_choose_kernel(GuideAxis x, GuideAxis y, const unsigned long long* costs,
                                    QuantileGuideKey* chosen) {
  const int a = static_cast<int>(threadIdx.x);
  if (a > 1) return;
  const GuideAxis& axis = a == 0 ? x : y;
  chosen[a] = costs[2 * a + 1] < costs[2 * a] ? axis.key(0) : axis.key(1);
}

constexpr int kBucketThreads = 256;
inline int bucket_blocks(std::size_t n) { return static_cast<int>((n + kBucketThreads - 1) / kBucketThreads); }

/// Points bucketed by cell: the grid's boundaries (quantile, from a sample of the points; or
/// uniform cells), every point's cell key, the points sorted by cell stably (within a cell, in
/// the order they came), and each cell's first position. Device memory for up to `capacity`
/// points, from the stream's pool. `shape` sizes the quantile cells and the room for cells;
/// uniform cells take `uniform_shape` (uniform_cells_shape: no more cells than `shape`).
class CellBuckets {
 public:
  /// `tuning`: its grid (Tuning::grid forces either kind) and tails.
  CellBuckets(std::size_t capacity, const GridShape& shape, const GridShape& uniform_shape, const Tuning& tuning,
              cudaStream_t stream)
      : shape_(shape),
        uniform_shape_(uniform_shape),
        cells_(static_cast<std::size_t>(shape.gx) * shape.gy),
        quantile_(tuning.grid != Tuning::Grid::uniform && capacity >= 64),
        quantile_forced_(tuning.grid == Tuning::Grid::quantile),
        tails_(tuning.tails),
        samples_(quantile_sample_count(capacity)),
        keys(capacity, stream),
        keys_sorted(capacity, stream),
        ids(capacity, stream),
        sorted_ids(capacity, stream),
        sorted(capacity, stream),
        cell_start(cells_ + 1, stream),
        // Room for the uniform shape's columns or rows, and for the square quantile shape's.
        xb_(quantile_ ? std::max(shape.gx, shape.gy) + 1 : 0, stream),
        yb_(quantile_ ? std::max(shape.gx, shape.gy) + 1 : 0, stream),
        x_guide_(quantile_ ? quantile_guide_capacity(std::max(shape.gx, shape.gy)) : 0, stream),
        y_guide_(quantile_ ? quantile_guide_capacity(std::max(shape.gx, shape.gy)) : 0, stream),
        x_even_(quantile_ ? quantile_guide_capacity(std::max(shape.gx, shape.gy)) : 0, stream),
        y_even_(quantile_ ? quantile_guide_capacity(std::max(shape.gx, shape.gy)) : 0, stream),
        sx_(quantile_ ? samples_ : 0, stream),
        sy_(quantile_ ? samples_ : 0, stream),
        sx2_(quantile_ ? samples_ : 0, stream),
        sy2_(quantile_ ? samples_ : 0, stream),
        bins_(quantile_ ? kEvennessBins * kEvennessBins : 0, stream),
        temp_(temp_bytes(capacity, stream), stream) {
    while ((std::size_t{1} << key_bits_) < cells_ + 1) ++key_bits_;
  }

  std::size_t cells() const { return cells_; }
  /// Whether the last build chose uniform cells.
  bool uniform() const { return uniform_; }
  /// Whether the last build's quantile cells have guides and heavy tails on the x-axis (kuzmin's,
  /// not a gaussian's: quantile_tails), which TailColumns serve.
  bool heavy_x_tails() const { return heavy_x_; }
  int key_bits() const { return key_bits_; }

  /// Buckets points[0, n) (n <= capacity): sets g's boundaries (g.xb, g.yb, quantile kind) and
  /// g.cell_start, g.points (the sorted points); rank, when given, gets each point's position.
  /// `word`: pinned host memory for the evenness test's one number; `guide_keys`: for the two axes'
  /// guide keys (the host waits for both); `heavy_word`: for whether the x-axis' tails are heavy
  /// (heavy_x_tails, read with the guide keys).
  void build(GridView& g, const double2* points, int n, int* rank, bool unordered_runs, unsigned int* word,
             QuantileGuideKey* guide_keys, unsigned int* heavy_word,
             cudaStream_t stream) {
    uniform_ = !quantile_;
    heavy_x_ = false;
    const int samples = quantile_sample_count(static_cast<std::size_t>(n));
    if (quantile_) {
      sample_kernel<<<bucket_blocks(samples), kBucketThreads, 0, stream>>>(points, n, samples, sx_.get(), sy_.get());
      EXPANSE_CUDA(cudaGetLastError());
      if (!quantile_forced_ && samples >= kEvennessMinSamples && g.max_x > g.min_x && g.max_y > g.min_y) {
        EXPANSE_CUDA(cudaMemsetAsync(bins_.get(), 0, bins_.bytes(), stream));
        evenness_count_kernel<<<std::min(64, bucket_blocks(samples)), kBucketThreads, 0, stream>>>(
            evenness_frame(g), sx_.get(), sy_.get(), samples, bins_.get());
        // The kernels write the read-backs into the pinned words themselves (mapped, as all pinned
        // memory is under unified addressing): a copy would queue behind the side stream's copies
        // of the sites to the host, which run beside the growth in the pipeline.
        evenness_max_kernel<<<1, kEvennessBins * kEvennessBins, 0, stream>>>(bins_.get(), word);
        EXPANSE_CUDA(cudaGetLastError());
        EXPANSE_CUDA(cudaStreamSynchronize(stream));
        uniform_ = evenly_spread(*word, samples);
      }
    }
    if (uniform_) {
      apply_shape(g, uniform_shape_);
    } else {
      // Quantile cells: as many columns as rows (quantile_shape), at most cells_ of them.
      const GridShape q = quantile_shape(shape_, Box{g.min_x, g.min_y, g.max_x, g.max_y});
      apply_shape(g, q);
      std::size_t bytes = temp_.bytes();
      EXPANSE_CUDA(cub::DeviceRadixSort::SortKeys(temp_.get(), bytes, sx_.get(), sx2_.get(), samples, 0, 64, stream));
      bytes = temp_.bytes();
      EXPANSE_CUDA(cub::DeviceRadixSort::SortKeys(temp_.get(), bytes, sy_.get(), sy2_.get(), samples, 0, 64, stream));
      const TailWeighing weighing = tails_;
      quantile_kernel<<<bucket_blocks(q.gx + 1), kBucketThreads, 0, stream>>>(sx2_.get(), samples, q.gx, weighing,
                                                                             xb_.get(), heavy_word);
      quantile_kernel<<<bucket_blocks(q.gy + 1), kBucketThreads, 0, stream>>>(sy2_.get(), samples, q.gy, weighing,
                                                                             yb_.get());
      EXPANSE_CUDA(cudaGetLastError());
      g.xb = xb_.get();
      g.yb = yb_.get();
      if (quantile_guided(q.gx) && quantile_guided(q.gy)) {
        // Each axis' guide chooses its key on the device; the host waits for the choice (quantile
        // cells only: the two sample sorts and the tables, well under a millisecond). The costs
        // are summed in the evenness test's histogram, done with (an array of their own, however
        // small, can move the pool's placement of the bucketing's arrays: StripBuffers).
        static_assert(kEvennessBins * kEvennessBins * sizeof(unsigned int) >= 4 * sizeof(unsigned long long));
        auto* const costs = reinterpret_cast<unsigned long long*>(bins_.get());
        const GuideAxis x{xb_.get(), q.gx, g.min_x, g.max_x, x_guide_.get(), x_even_.get()};
        const GuideAxis y{yb_.get(), q.gy, g.min_y, g.max_y, y_guide_.get(), y_even_.get()};
        EXPANSE_CUDA(cudaMemsetAsync(costs, 0, 4 * sizeof(unsigned long long), stream));
        const int entries = quantile_guide_capacity(std::max(q.gx, q.gy));
        guide_tables_kernel<<<dim3((entries + kGuideThreads - 1) / kGuideThreads, 2, 2), kGuideThreads, 0, stream>>>(
            x, y, costs);
        guide_choose_kernel<<<1, 32, 0, stream>>>(x, y, costs, guide_keys);
        EXPANSE_CUDA(cudaGetLastError());
        EXPANSE_CUDA(cudaStreamSynchronize(stream));
        g.x_guide = {guide_keys[0].logarithmic ? x_guide_.get() : x_even_.get(), guide_keys[0]};
        heavy_x_ = *heavy_word != 0u;
        g.y_guide = {guide_keys[1].logarithmic ? y_guide_.get() : y_even_.get(), guide_keys[1]};
      }
    }
    // Where the sites hold long runs of equal Morton codes in no spatial order
    // (`unordered_runs`: the device's preparation leaves such a run in input order, the host's
    // puts it in (x, y) order), a cell's sites are walked in x order instead of the sites' order.
    // Kuzmin's centre, finer than the quantisation, has thousands of sites a code at 4096^2, each
    // code's spread over hundreds of cells: in input order the second phase's parity fell at
    // random there, and it searched for 5.26 M sites where the host's order left 4.58 M; in x
    // order 4.59 M, and the star stage 46.5 -> 45.2 ms (H100, kuzmin 4096^2). Elsewhere the
    // sites' order (Morton) serves better: with every quantile cell's sites in a spatial order,
    // gaussian lost 0.5 ms at 4096^2.
    const bool within = unordered_runs && key_bits_ + kSubCellBits <= 32;
    const int shift = within ? kSubCellBits : 0;
    cell_keys_kernel<<<bucket_blocks(n), kBucketThreads, 0, stream>>>(g, points, n, keys.get(), ids.get(), within);
    EXPANSE_CUDA(cudaGetLastError());
    std::size_t bytes = temp_.bytes();
    EXPANSE_CUDA(cub::DeviceRadixSort::SortPairs(temp_.get(), bytes, keys.get(), keys_sorted.get(), ids.get(),
                                                 sorted_ids.get(), n, 0, key_bits_ + shift, stream));
    gather_kernel<<<bucket_blocks(n), kBucketThreads, 0, stream>>>(sorted_ids.get(), points, n, sorted.get(), rank);
    if (within) cells_of_keys_kernel<<<bucket_blocks(n), kBucketThreads, 0, stream>>>(keys_sorted.get(), n, shift);
    EXPANSE_CUDA(cudaGetLastError());
    // The cells of the shape applied, not the room for them: the last site's thread fills the
    // starts of the cells after its own alone (uniform cells, coarser than the room, left 3.6M
    // of them to one thread at 4096^2: the bucket stage 1.1 -> 14.3 ms).
    cell_start_kernel<<<bucket_blocks(n), kBucketThreads, 0, stream>>>(keys_sorted.get(), n, g.gx * g.gy,
                                                                       cell_start.get());
    EXPANSE_CUDA(cudaGetLastError());
    g.cell_start = cell_start.get();
    g.points = sorted.get();
  }

 private:
  std::size_t temp_bytes(std::size_t capacity, cudaStream_t stream) const {
    std::size_t sort_bytes = 0, sample_bytes = 0;
    EXPANSE_CUDA(cub::DeviceRadixSort::SortPairs(nullptr, sort_bytes, static_cast<std::uint32_t*>(nullptr),
                                                 static_cast<std::uint32_t*>(nullptr), static_cast<int*>(nullptr),
                                                 static_cast<int*>(nullptr), static_cast<int>(capacity), 0, 32,
                                                 stream));
    if (quantile_)
      EXPANSE_CUDA(cub::DeviceRadixSort::SortKeys(nullptr, sample_bytes, static_cast<double*>(nullptr),
                                                  static_cast<double*>(nullptr), samples_, 0, 64, stream));
    return std::max(sort_bytes, sample_bytes);
  }

  GridShape shape_, uniform_shape_;
  std::size_t cells_;
  bool quantile_;   ///< quantile cells possible (not Tuning::Grid::uniform, not tiny)
  bool quantile_forced_;  ///< quantile cells whatever the evenness test (Tuning::Grid::quantile)
  TailWeighing tails_;
  bool uniform_ = false;  ///< the last build's choice
  bool heavy_x_ = false;  ///< the last build's quantile cells: guides, and heavy x-tails
  int samples_;
  int key_bits_ = 1;

 public:
  DeviceArray<std::uint32_t> keys, keys_sorted;
  DeviceArray<int> ids, sorted_ids;  ///< sorted_ids[position] = the point's index in `points`
  DeviceArray<double2> sorted;
  DeviceArray<std::uint32_t> cell_start;

 private:
  DeviceArray<double> xb_, yb_;
  DeviceArray<int> x_guide_, y_guide_;  ///< the logarithmic keys' tables
  DeviceArray<int> x_even_, y_even_;    ///< the even keys' tables
  DeviceArray<double> sx_, sy_, sx2_, sy2_;
  DeviceArray<unsigned int> bins_;  ///< the evenness histogram
  DeviceArray<unsigned char> temp_;
};

}  // namespace
}  // namespace expanse::detail::cuda
