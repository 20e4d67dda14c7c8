// The raw input prepared on the device, as prepare_sites does it on the host: scaled by the
// power of two the host's scan chose, duplicates merged (the smallest input index represents
// each group), the sites put in Morton order; then grown by the per-site layout.
//
//   upload raw points -> scale -> bucket by cell (stable: input order within a cell)
//     -> merge: a point equal to an earlier one of its cell joins that one's group
//     -> compact the groups' first points -> Morton codes -> sort: the sites' order
//     -> download the sites, their input indices, the representatives and the hull's site ids
//     -> grow_per_site on the sites already on the device
//
// On the host this took 125-170 ms at 4096^2 on 16 threads (session 5, the H100's host): the
// sorting and merging is the device's to do, and the host only validates and finds the hull.
// Equal points share a cell, so merging looks only through cells; a cell crowded past
// kMergeCellLimit (many copies of few points) is left to the host (grow_from_input declines).
#include <cub/device/device_radix_sort.cuh>
#include <cub/device/device_scan.cuh>

#include <chrono>
#include <cmath>
#include <cstring>
#include <future>
#include <optional>
#include <ranges>

#include "bucket_kernels.cuh"
#include "cuda_internal.hpp"
#include "input/morton.hpp"
#include "input/parallel.hpp"

namespace expanse::detail::cuda {
namespace {

/// Past this many points in a cell, the pairwise look for equal points is left to the host.
constexpr int kMergeCellLimit = 64;
constexpr int kThreads = 256;
int blocks_for(std::size_t n) { return static_cast<int>((n + kThreads - 1) / kThreads); }

/// p * 2^e, exact: as InputScan::scaled (a multiplication by `factor`, or scalbn past 2^1023).
__global__ void scale_kernel(double2* points, int n, int e, double factor) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= n) return;
  double2 p = points[i];
  if (e <= 1023) {
    p.x = __dmul_rn(p.x, factor);
    p.y = __dmul_rn(p.y, factor);
  } else {
    p.x = scalbn(p.x, e);
    p.y = scalbn(p.y, e);
  }
  points[i] = p;
}

/// first[p]: the first position of p's cell holding a point equal to p's (p itself if none);
/// head[p] = 1 where that is p. Positions within a cell are in input order, so the first is the
/// smallest input index. flags[0] is set when a cell holds more than kMergeCellLimit points.
__global__ void first_equal_kernel(const double2* sorted, const std::uint32_t* keys, const std::uint32_t* cell_start,
                                   int n, int* first, int* head, unsigned int* flags) {
  const int p = blockIdx.x * blockDim.x + threadIdx.x;
  if (p >= n) return;
  const std::uint32_t cell = keys[p];
  const int begin = static_cast<int>(cell_start[cell]), end = static_cast<int>(cell_start[cell + 1]);
  int q = p;
  if (end - begin > kMergeCellLimit) {
    atomicOr(flags, 1u);
  } else {
    const double2 v = sorted[p];
    for (int j = begin; j < p; ++j) {
      const double2 w = sorted[j];
      if (w.x == v.x && w.y == v.y) {
        q = j;
        break;
      }
    }
  }
  first[p] = q;
  head[p] = q == p;
}

/// Groups -> distinct points: position p's group is local id slot[first[p]]. rank_input maps
/// every input index to its group's local id, representative to the group's first input index.
__global__ void compact_kernel(const double2* sorted, const int* sorted_input, const int* first, const int* head,
                               const int* slot, int n, double2* local_points, int* local_input, int* rank_input,
                               int* representative) {
  const int p = blockIdx.x * blockDim.x + threadIdx.x;
  if (p >= n) return;
  const int input = sorted_input[p], f = first[p];
  if (head[p]) {
    local_points[slot[p]] = sorted[p];
    local_input[slot[p]] = input;
  }
  rank_input[input] = slot[f];
  representative[input] = sorted_input[f];
}

struct QuantiserView {
  double origin_x, origin_y, scale;
};

__device__ __forceinline__ std::uint32_t quantise(double v, double origin, double scale) {
  // As Quantiser::x: (v - origin) * scale, clamped to [0, max], truncated; no contraction.
  const double q = __dmul_rn(__dsub_rn(v, origin), scale);
  if (!(q > 0.0)) return 0;
  if (q >= static_cast<double>(Quantiser::max)) return Quantiser::max;
  return static_cast<std::uint32_t>(q);
}

__device__ __forceinline__ std::uint64_t spread_bits(std::uint32_t v) {
  std::uint64_t x = v;
  x = (x | (x << 16)) & 0x0000FFFF0000FFFFull;
  x = (x | (x << 8)) & 0x00FF00FF00FF00FFull;
  x = (x | (x << 4)) & 0x0F0F0F0F0F0F0F0Full;
  x = (x | (x << 2)) & 0x3333333333333333ull;
  x = (x | (x << 1)) & 0x5555555555555555ull;
  return x;
}

/// The Morton code of local site l, as morton_code(quantiser.x(p.x), quantiser.y(p.y)).
__global__ void morton_kernel(const double2* points, int m, QuantiserView q, std::uint64_t* codes, int* ids) {
  const int l = blockIdx.x * blockDim.x + threadIdx.x;
  if (l >= m) return;
  const double2 p = points[l];
  codes[l] = spread_bits(quantise(p.x, q.origin_x, q.scale)) | (spread_bits(quantise(p.y, q.origin_y, q.scale)) << 1);
  ids[l] = l;
}

/// Site s (Morton order) is local site site_local[s].
__global__ void site_order_kernel(const int* site_local, const double2* local_points, const int* local_input, int m,
                                  double2* site_points, int* site_input, int* local_site) {
  const int s = blockIdx.x * blockDim.x + threadIdx.x;
  if (s >= m) return;
  const int l = site_local[s];
  site_points[s] = local_points[l];
  site_input[s] = local_input[l];
  local_site[l] = s;
}

/// The hull's input indices (representatives) -> site ids.
__global__ void hull_sites_kernel(const int* hull_input, int h, const int* rank_input, const int* local_site,
                                  int* hull_sites) {
  const int t = blockIdx.x * blockDim.x + threadIdx.x;
  if (t >= h) return;
  hull_sites[t] = local_site[rank_input[hull_input[t]]];
}

}  // namespace

bool grow_per_site_from_input(Context& ctx, const InputGrowInput& input, InputGrowResult& result) {
  using clock = std::chrono::steady_clock;
  const cudaStream_t stream = ctx.stream;
  const std::size_t n = input.points.size();
  const std::size_t h = input.hull.size();
  if (n >= (std::size_t{1} << 30)) return false;  // the host's path refuses it, with the error
  const Box& bounds = input.scan.bounds;
  const GridShape shape = make_grid_shape(bounds, n, input.layout.sites_per_bucket);
  // Raw and sorted points, cell keys and ids twice, the merge's three arrays, the maps.
  require_device_memory(n * (4 * sizeof(double2) + 2 * sizeof(std::uint64_t) + 12 * sizeof(int)) +
                            static_cast<std::size_t>(shape.gx) * shape.gy * sizeof(std::uint32_t),
                        n, "points");

  // Every point its own representative, written on another host thread while the device works
  // (the usual case; the device's map replaces it where points repeat).
  SiteSet& sites = result.sites;
  auto identity = std::async(std::launch::async, [&sites, n] {
    auto& representative = sites.representative;
    representative.reserve(n);
    advise_huge_pages(representative.data(), n * sizeof(std::int32_t));
    const auto ids = std::views::iota(std::int32_t{0}, static_cast<std::int32_t>(n));
    representative.assign(ids.begin(), ids.end());
  });

  StageTimer timer(stream);
  const auto host_start = clock::now();
  std::size_t m = 0;
  std::optional<DeviceArray<double2>> d_site_points;
  std::optional<DeviceArray<int>> d_site_input, d_hull_sites;
  DeviceArray<int> d_representative(n, stream);
  clock::time_point host_uploaded;
  {
    DeviceArray<double2> d_raw(n, stream);
    DeviceArray<int> d_hull_input(h, stream);
    timer.begin("upload");
    static_assert(sizeof(Point2) == sizeof(double2));
    ctx.staging->upload(d_raw.get(), input.points.data(), n * sizeof(double2), stream);
    ctx.staging->upload(d_hull_input.get(), input.hull.data(), h * sizeof(int), stream);
    timer.end();
    host_uploaded = clock::now();

    CellBuckets buckets(n, shape, stream);
    DeviceArray<int> d_first(n, stream), d_head(n, stream), d_slot(n, stream);
    DeviceArray<unsigned int> d_flags(1, stream);
    std::size_t scan_bytes = 0;
    EXPANSE_CUDA(cub::DeviceScan::ExclusiveSum(nullptr, scan_bytes, d_head.get(), d_slot.get(), static_cast<int>(n),
                                               stream));
    DeviceArray<unsigned char> d_scan_temp(scan_bytes, stream);
    timer.begin("merge duplicates");
    scale_kernel<<<blocks_for(n), kThreads, 0, stream>>>(d_raw.get(), static_cast<int>(n), input.scan.scale_exponent,
                                                          input.scan.factor);
    EXPANSE_CUDA(cudaGetLastError());
    GridView g = make_grid_view(shape, bounds);
    buckets.build(g, d_raw.get(), static_cast<int>(n), nullptr, stream);
    EXPANSE_CUDA(cudaMemsetAsync(d_flags.get(), 0, sizeof(unsigned int), stream));
    first_equal_kernel<<<blocks_for(n), kThreads, 0, stream>>>(buckets.sorted.get(), buckets.keys_sorted.get(),
                                                               buckets.cell_start.get(), static_cast<int>(n),
                                                               d_first.get(), d_head.get(), d_flags.get());
    EXPANSE_CUDA(cudaGetLastError());
    EXPANSE_CUDA(cub::DeviceScan::ExclusiveSum(d_scan_temp.get(), scan_bytes, d_head.get(), d_slot.get(),
                                               static_cast<int>(n), stream));
    // Whether a cell was too crowded, and how many groups (the last slot plus the last head).
    unsigned int* const words = ctx.pinned_words;
    EXPANSE_CUDA(cudaMemcpyAsync(&words[0], d_flags.get(), sizeof(unsigned int), cudaMemcpyDeviceToHost, stream));
    EXPANSE_CUDA(cudaMemcpyAsync(&words[1], d_slot.get() + n - 1, sizeof(int), cudaMemcpyDeviceToHost, stream));
    EXPANSE_CUDA(cudaMemcpyAsync(&words[2], d_head.get() + n - 1, sizeof(int), cudaMemcpyDeviceToHost, stream));
    timer.end();
    EXPANSE_CUDA(cudaStreamSynchronize(stream));
    if (words[0] != 0) return false;  // a crowded cell: the host merges
    m = static_cast<std::size_t>(words[1]) + words[2];

    timer.begin("sites in Morton order");
    DeviceArray<double2> d_local_points(m, stream);
    DeviceArray<int> d_local_input(m, stream), d_rank_input(n, stream);
    compact_kernel<<<blocks_for(n), kThreads, 0, stream>>>(buckets.sorted.get(), buckets.sorted_ids.get(), d_first.get(),
                                                           d_head.get(), d_slot.get(), static_cast<int>(n),
                                                           d_local_points.get(), d_local_input.get(),
                                                           d_rank_input.get(), d_representative.get());
    EXPANSE_CUDA(cudaGetLastError());
    // The sites' order: Morton codes as prepare_sites and the seam's bucket tree compute them.
    const Quantiser quantiser(bounds);
    DeviceArray<std::uint64_t> d_codes(m, stream), d_codes_sorted(m, stream);
    DeviceArray<int> d_ids(m, stream), d_site_local(m, stream), d_local_site(m, stream);
    morton_kernel<<<blocks_for(m), kThreads, 0, stream>>>(d_local_points.get(), static_cast<int>(m),
                                                          {quantiser.origin_x, quantiser.origin_y, quantiser.scale},
                                                          d_codes.get(), d_ids.get());
    EXPANSE_CUDA(cudaGetLastError());
    std::size_t sort_bytes = 0;
    EXPANSE_CUDA(cub::DeviceRadixSort::SortPairs(nullptr, sort_bytes, d_codes.get(), d_codes_sorted.get(), d_ids.get(),
                                                 d_site_local.get(), static_cast<int>(m), 0, 2 * Quantiser::bits,
                                                 stream));
    DeviceArray<unsigned char> d_sort_temp(sort_bytes, stream);
    EXPANSE_CUDA(cub::DeviceRadixSort::SortPairs(d_sort_temp.get(), sort_bytes, d_codes.get(), d_codes_sorted.get(),
                                                 d_ids.get(), d_site_local.get(), static_cast<int>(m), 0,
                                                 2 * Quantiser::bits, stream));
    d_site_points.emplace(m, stream);
    d_site_input.emplace(m, stream);
    d_hull_sites.emplace(h, stream);
    site_order_kernel<<<blocks_for(m), kThreads, 0, stream>>>(d_site_local.get(), d_local_points.get(),
                                                              d_local_input.get(), static_cast<int>(m),
                                                              d_site_points->get(), d_site_input->get(),
                                                              d_local_site.get());
    EXPANSE_CUDA(cudaGetLastError());
    hull_sites_kernel<<<blocks_for(h), kThreads, 0, stream>>>(d_hull_input.get(), static_cast<int>(h),
                                                              d_rank_input.get(), d_local_site.get(),
                                                              d_hull_sites->get());
    EXPANSE_CUDA(cudaGetLastError());
    timer.end();
  }

  // The host's copy of what it prepared: the seam stage and the output need the sites, the
  // input indices and the representatives; the hull in site ids.
  sites.scale_exponent = input.scan.scale_exponent;
  sites.bounds = bounds;
  resize_for_parallel_write(sites.points, m);
  resize_for_parallel_write(sites.input_index, m);
  Hull& hull = result.hull;
  hull.sites.resize(h);
  timer.begin("download sites");
  ctx.staging->download(sites.points.data(), d_site_points->get(), m * sizeof(double2), stream);
  ctx.staging->download(sites.input_index.data(), d_site_input->get(), m * sizeof(int), stream);
  ctx.staging->download(hull.sites.data(), d_hull_sites->get(), h * sizeof(int), stream);
  identity.get();
  if (m < n) ctx.staging->download(sites.representative.data(), d_representative.get(), n * sizeof(int), stream);
  timer.end();
  const auto host_downloaded = clock::now();
  resize_for_parallel_write(hull.predecessor, m);
  parallel_chunks(m, [&](std::size_t, std::size_t begin, std::size_t end) {
    std::fill(hull.predecessor.begin() + static_cast<std::ptrdiff_t>(begin),
              hull.predecessor.begin() + static_cast<std::ptrdiff_t>(end), -1);
  });
  for (std::size_t k = 0; k < h; ++k) hull.predecessor[hull.sites[k]] = hull.sites[(k + h - 1) % h];
  const auto host_prepared = clock::now();

  std::vector<StageTime> prepare_stages = timer.collect();
  const SitesOnDevice on_device{d_site_points->get(), d_hull_sites->get()};
  grow_per_site(ctx, GrowInput{sites, hull, input.layout, input.recycled}, result.grown, &on_device);
  auto& stages = result.grown.device_stages;
  stages.insert(stages.begin(), prepare_stages.begin(), prepare_stages.end());
  auto ms = [](auto a, auto b) { return std::chrono::duration<double, std::milli>(b - a).count(); };
  auto& host = result.grown.host_stages;
  host.insert(host.begin(), {{"cuda upload of the input (host)", ms(host_start, host_uploaded)},
                             {"cuda prepare on the device (host wait)", ms(host_uploaded, host_downloaded)},
                             {"cuda host copy of the sites and hull", ms(host_downloaded, host_prepared)}});
  last_run_counters().bytes_to_device = n * sizeof(double2) + h * sizeof(int);
  last_run_counters().bytes_to_host +=
      m * (sizeof(double2) + sizeof(int)) + h * sizeof(int) + (m < n ? n * sizeof(int) : 0);
  return true;
}

}  // namespace expanse::detail::cuda
