// The paper's block layout (docs/algorithm.md, "GPU, the paper's layout"): B x B blocks, each
// with K x K buckets over its own square plus a halo copied from its neighbours; one seed per
// block; one CUDA thread block per block iterates over its active edges until every block's
// front is empty. An expansion is accepted only when it is decided exactly and its
// circle-and-left-half-plane box lies inside the block's copy, so every accepted triangle is a
// triangle of the global Delaunay triangulation; a triangle is emitted only by the block that
// owns its smallest site id. Everything else is left to the CPU seam stage.
#include <cub/device/device_radix_sort.cuh>
#include <cub/device/device_scan.cuh>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "cuda_internal.hpp"
#include "support/timing.hpp"
#include "device_geometry.cuh"
#include "sorted_order_kernels.cuh"

namespace expanse::detail::cuda {
namespace {

constexpr unsigned long long kEmpty = ~0ull;

/// The block decomposition; every kernel derives a block's boxes from it the same way.
struct Blocks {
  double min_x, min_y, block_w, block_h, inv_bw, inv_bh, halo;
  int side;     ///< B
  int buckets;  ///< K

  __device__ __forceinline__ int own_x(double x) const {
    const double t = ex::mul(ex::sub(x, min_x), inv_bw);
    if (!(t >= 0.0)) return 0;
    if (t >= side - 1) return side - 1;
    return static_cast<int>(t);
  }
  __device__ __forceinline__ int own_y(double y) const {
    const double t = ex::mul(ex::sub(y, min_y), inv_bh);
    if (!(t >= 0.0)) return 0;
    if (t >= side - 1) return side - 1;
    return static_cast<int>(t);
  }
  __device__ __forceinline__ int own(double2 p) const { return own_y(p.y) * side + own_x(p.x); }
  /// The block's copy region: its square widened by the halo on every side (closed box).
  __device__ __forceinline__ void region(int b, double* x0, double* x1, double* y0, double* y1) const {
    const int bx = b % side, by = b / side;
    *x0 = min_x + (bx - halo) * block_w;
    *x1 = min_x + (bx + 1 + halo) * block_w;
    *y0 = min_y + (by - halo) * block_h;
    *y1 = min_y + (by + 1 + halo) * block_h;
  }
  __device__ __forceinline__ bool in_region(int b, double2 p) const {
    double x0, x1, y0, y1;
    region(b, &x0, &x1, &y0, &y1);
    return p.x >= x0 && p.x <= x1 && p.y >= y0 && p.y <= y1;
  }
  __device__ __forceinline__ GridView grid(int b, const std::uint32_t* cell_start, const double2* points) const {
    double x0, x1, y0, y1;
    region(b, &x0, &x1, &y0, &y1);
    GridView g{};
    g.min_x = x0;
    g.min_y = y0;
    g.inv_w = buckets / (x1 - x0);
    g.inv_h = buckets / (y1 - y0);
    g.cell_w = (x1 - x0) / buckets;
    g.cell_h = (y1 - y0) / buckets;
    g.gx = g.gy = buckets;
    g.max_x = x1;
    g.max_y = y1;
    g.cell_start = cell_start + static_cast<std::size_t>(b) * buckets * buckets;
    g.points = points;
    return g;
  }
  __device__ __forceinline__ int reach() const { return static_cast<int>(ceil(halo)); }
};

__global__ void membership_count_kernel(Blocks bl, const double2* points, int n, int* count) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= n) return;
  const double2 p = points[i];
  const int ox = bl.own_x(p.x), oy = bl.own_y(p.y), r = bl.reach();
  int c = 0;
  for (int by = max(0, oy - r); by <= min(bl.side - 1, oy + r); ++by)
    for (int bx = max(0, ox - r); bx <= min(bl.side - 1, ox + r); ++bx)
      c += bl.in_region(by * bl.side + bx, p) || (bx == ox && by == oy);
  count[i] = c;
}

__global__ void membership_fill_kernel(Blocks bl, const double2* points, int n, const int* offset,
                                       std::uint32_t* keys, int* sites) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= n) return;
  const double2 p = points[i];
  const int ox = bl.own_x(p.x), oy = bl.own_y(p.y), r = bl.reach();
  int out = offset[i];
  for (int by = max(0, oy - r); by <= min(bl.side - 1, oy + r); ++by)
    for (int bx = max(0, ox - r); bx <= min(bl.side - 1, ox + r); ++bx) {
      const int b = by * bl.side + bx;
      if (!(bl.in_region(b, p) || (bx == ox && by == oy))) continue;
      const GridView g = bl.grid(b, nullptr, nullptr);
      keys[out] = static_cast<std::uint32_t>(b * bl.buckets * bl.buckets + g.cell_y(p.y) * bl.buckets + g.cell_x(p.x));
      sites[out] = i;
      ++out;
    }
}

/// Per-block capacities: the hash set of finished directed edges and the two edge lists.
__global__ void block_sizes_kernel(const std::uint32_t* cell_start, int blocks, int cells_per_block, int* hash_cap,
                                   int* list_cap) {
  const int b = blockIdx.x * blockDim.x + threadIdx.x;
  if (b >= blocks) return;
  const int sites = static_cast<int>(cell_start[(b + 1) * cells_per_block] - cell_start[b * cells_per_block]);
  hash_cap[b] = 8 * sites + 64;  // <= 6 sites directed edges: load below 0.75
  list_cap[b] = 6 * sites + 16;  // every directed edge is queued at most once (seeds twice)
}

__device__ __forceinline__ unsigned long long edge_key(int a, int b) {
  return (static_cast<unsigned long long>(static_cast<unsigned>(a)) << 32) | static_cast<unsigned>(b);
}

__device__ __forceinline__ unsigned hash_slot(unsigned long long key, unsigned cap) {
  key ^= key >> 33;
  key *= 0xff51afd7ed558ccdull;
  key ^= key >> 33;
  return static_cast<unsigned>(key % cap);
}

/// True if this call inserted the key (false: it was already there, or the table is full).
__device__ inline bool set_insert(unsigned long long* table, unsigned cap, unsigned long long key) {
  unsigned s = hash_slot(key, cap);
  for (unsigned probe = 0; probe < cap; ++probe) {
    const unsigned long long prev = atomicCAS(table + s, kEmpty, key);
    if (prev == kEmpty) return true;
    if (prev == key) return false;
    s = s + 1 == cap ? 0 : s + 1;
  }
  return false;
}

__device__ inline bool set_contains(const unsigned long long* table, unsigned cap, unsigned long long key) {
  unsigned s = hash_slot(key, cap);
  for (unsigned probe = 0; probe < cap; ++probe) {
    const unsigned long long v = *reinterpret_cast<const volatile unsigned long long*>(table + s);
    if (v == key) return true;
    if (v == kEmpty) return false;
    s = s + 1 == cap ? 0 : s + 1;
  }
  return false;
}

struct BlockState {
  Blocks bl;
  const std::uint32_t* cell_start;
  const double2* points;  ///< block copies, sorted by (block, bucket)
  const int* sites;       ///< block copy -> site id
  const int* pred;        ///< site id -> hull predecessor (-1)
  const double2* site_points;
  const int* hash_offset;
  const int* hash_cap;
  unsigned long long* done;
  const int* list_offset;
  const int* list_cap;
  int2* current;
  int* current_count;
  int2* next;
  int* next_count;
  int* triangles;
  unsigned triangle_capacity;
  unsigned int* counters;  ///< [0] triangles emitted, [1] open edges, [2..3] predicates (u64)
};

__device__ inline void push_edge(const BlockState& s, int b, int ja, int jb) {
  const int slot = atomicAdd(s.next_count + b, 1);
  if (slot < s.list_cap[b]) s.next[s.list_offset[b] + slot] = make_int2(ja, jb);
  else atomicAdd(s.counters + 1, 1u);  // dropped: stays open for the seam stage
}

/// One thread block per block: the seed is the own site nearest the block centre; its first
/// edges go to the seed's exact nearest neighbour when that lies provably inside the copy.
__global__ void seed_kernel(BlockState s) {
  const int b = blockIdx.x;
  const int cells = s.bl.buckets * s.bl.buckets;
  const int begin = static_cast<int>(s.cell_start[b * cells]), end = static_cast<int>(s.cell_start[(b + 1) * cells]);
  double x0, x1, y0, y1;
  s.bl.region(b, &x0, &x1, &y0, &y1);
  const double cx = s.bl.min_x + (b % s.bl.side + 0.5) * s.bl.block_w;
  const double cy = s.bl.min_y + (b / s.bl.side + 0.5) * s.bl.block_h;
  double best_d = 1e300;
  int best = -1;
  for (int j = begin + threadIdx.x; j < end; j += blockDim.x) {
    const double2 p = s.points[j];
    if (s.bl.own(p) != b) continue;
    const double d = (p.x - cx) * (p.x - cx) + (p.y - cy) * (p.y - cy);
    if (d < best_d || (d == best_d && j < best)) best_d = d, best = j;
  }
  __shared__ double shared_d[1024];
  __shared__ int shared_j[1024];
  shared_d[threadIdx.x] = best_d;
  shared_j[threadIdx.x] = best;
  __syncthreads();
  if (threadIdx.x != 0) return;
  for (int t = 1; t < static_cast<int>(blockDim.x); ++t)
    if (shared_j[t] >= 0 && (best < 0 || shared_d[t] < best_d || (shared_d[t] == best_d && shared_j[t] < best)))
      best_d = shared_d[t], best = shared_j[t];
  if (best < 0) return;
  const GridView g = s.bl.grid(b, s.cell_start, s.points);
  bool ok = true;
  const double2 p = s.points[best];
  const int nn = nearest_site(g, best, p, &ok);
  if (!ok || nn < 0) return;
  // The copy's nearest is the global nearest only if no site outside the copy can be closer.
  const double border = fmin(fmin(p.x - x0, x1 - p.x), fmin(p.y - y0, y1 - p.y));
  if (!(sqrt(dist2(p, s.points[nn])) < border * (1.0 - 1e-9))) return;
  const int a = s.sites[best], c = s.sites[nn];
  if (s.pred[a] != c) push_edge(s, b, best, nn);
  if (s.pred[c] != a) push_edge(s, b, nn, best);
}

__global__ void expand_kernel(BlockState s) {
  const int b = blockIdx.x;
  const int count = min(s.current_count[b], s.list_cap[b]);
  const unsigned cap = static_cast<unsigned>(s.hash_cap[b]);
  unsigned long long* done = s.done + s.hash_offset[b];
  const GridView g = s.bl.grid(b, s.cell_start, s.points);
  double x0, x1, y0, y1;
  s.bl.region(b, &x0, &x1, &y0, &y1);
  unsigned predicates = 0, cells = 0;
  for (int t = threadIdx.x; t < count; t += blockDim.x) {
    const int2 e = s.current[s.list_offset[b] + t];
    const int ja = e.x, jb = e.y;
    if (set_contains(done, cap, edge_key(ja, jb))) continue;
    const double2 pa = s.points[ja], pb = s.points[jb];
    int status;
    const int jc = find_apex(g, ja, pa, jb, pb, &status, &predicates, &cells, 0xffffffffu);
    if (status != apex_found) {
      atomicAdd(s.counters + 1, 1u);
      continue;
    }
    const double2 pc = s.points[jc];
    double xl, xh, yl, yh;
    if (!cap_box(pa, pb, pc, &xl, &xh, &yl, &yh) || xl < x0 || xh > x1 || yl < y0 || yh > y1) {
      atomicAdd(s.counters + 1, 1u);  // a site outside this copy could lie in the circle
      continue;
    }
    // Claim the triangle by its edge leaving the smallest copy index: exactly one of the active
    // edges that found it in this iteration wins.
    int m0 = ja, m1 = jb, m2 = jc;
    if (jb < m0 && jb < jc) m0 = jb, m1 = jc, m2 = ja;
    else if (jc < m0 && jc < jb) m0 = jc, m1 = ja, m2 = jb;
    if (!set_insert(done, cap, edge_key(m0, m1))) continue;
    set_insert(done, cap, edge_key(m1, m2));
    set_insert(done, cap, edge_key(m2, m0));
    const int a = s.sites[ja], bb = s.sites[jb], c = s.sites[jc];
    int lowest = a;
    double2 lowest_p = pa;
    if (bb < lowest) lowest = bb, lowest_p = pb;
    if (c < lowest) lowest = c, lowest_p = pc;
    if (s.bl.own(lowest_p) == b) {
      const unsigned slot = atomicAdd(s.counters, 1u);
      if (slot >= s.triangle_capacity) continue;  // impossible for a correct run; never write past the end
      s.triangles[3 * static_cast<std::size_t>(slot) + 0] = a;
      s.triangles[3 * static_cast<std::size_t>(slot) + 1] = bb;
      s.triangles[3 * static_cast<std::size_t>(slot) + 2] = c;
    }
    // Outward edges: the reverses of the triangle's edges, unless finished or outer.
    const int jt[3] = {ja, jb, jc};
    const int st[3] = {a, bb, c};
    for (int k = 0; k < 3; ++k) {
      const int jx = jt[(k + 1) % 3], jy = jt[k];  // reverse of jt[k] -> jt[k+1]
      const int sx = st[(k + 1) % 3], sy = st[k];
      if (s.pred[sx] == sy) continue;
      if (set_contains(done, cap, edge_key(jx, jy))) continue;
      push_edge(s, b, jx, jy);
    }
  }
  const unsigned active = __activemask();
  const unsigned warp_total = __reduce_add_sync(active, predicates);
  if ((threadIdx.x & 31) == __ffs(active) - 1)
    atomicAdd(reinterpret_cast<unsigned long long*>(s.counters + 2), static_cast<unsigned long long>(warp_total));
}

__global__ void sum_kernel(const int* count, const int* cap, int blocks, int* total) {
  int sum = 0;
  for (int b = threadIdx.x; b < blocks; b += blockDim.x) sum += min(count[b], cap[b]);
  sum = __reduce_add_sync(0xffffffffu, sum);
  __shared__ int partial[32];
  if ((threadIdx.x & 31) == 0) partial[threadIdx.x / 32] = sum;
  __syncthreads();
  if (threadIdx.x == 0) {
    int t = 0;
    for (int w = 0; w < static_cast<int>(blockDim.x / 32); ++w) t += partial[w];
    *total = t;
  }
}

__global__ void predecessor_kernel(const int* hull, int h, int* pred) {
  const int t = blockIdx.x * blockDim.x + threadIdx.x;
  if (t < h) pred[hull[t]] = hull[t == 0 ? h - 1 : t - 1];
}

int grid_for(std::size_t n, int threads = 256) { return static_cast<int>((n + threads - 1) / threads); }

}  // namespace

void grow_paper_blocks(Context& ctx, const GrowInput& input, GrowResult& result) {
  const cudaStream_t stream = ctx.stream;
  const Layout& layout = input.layout;
  const auto& sites = input.sites;
  const std::size_t n = sites.points.size();
  if (layout.blocks_per_side < 1 || layout.buckets_per_block_side < 1 || layout.blocks_per_side > 256 ||
      layout.buckets_per_block_side > 256 || !(layout.halo_fraction >= 0.0 && layout.halo_fraction <= 1.0))
    throw Error(ErrorCode::invalid_argument,
                "CUDA paper layout: need 1..256 blocks and buckets per side and a halo fraction in [0, 1]");
  const int side = layout.blocks_per_side, buckets = layout.buckets_per_block_side;
  const int blocks = side * side;
  const std::size_t cells = static_cast<std::size_t>(blocks) * buckets * buckets;
  if (n >= (std::size_t{1} << 28) || cells >= (std::size_t{1} << 31))
    throw Error(ErrorCode::too_large, "CUDA paper layout: too many sites or buckets");

  Blocks bl{};
  bl.side = side;
  bl.buckets = buckets;
  bl.halo = layout.halo_fraction;
  bl.min_x = sites.bounds.min_x;
  bl.min_y = sites.bounds.min_y;
  const double w = std::max(sites.bounds.max_x - sites.bounds.min_x, 1e-300);
  const double h = std::max(sites.bounds.max_y - sites.bounds.min_y, 1e-300);
  bl.block_w = w / side;
  bl.block_h = h / side;
  bl.inv_bw = side / w;
  bl.inv_bh = side / h;
  int threads = layout.threads_per_block;
  if (threads <= 0) threads = static_cast<int>(std::sqrt(static_cast<double>(n) / blocks));
  threads = std::clamp((threads + 31) / 32 * 32, 32, 1024);

  StageTimer timer(stream);
  const auto host_start = Clock::now();
  DeviceArray<double2> d_points(n, stream);
  DeviceArray<int> d_hull(input.hull.sites.size(), stream), d_pred(n, stream);
  timer.begin("upload");
  ctx.staging->upload(d_points.get(), sites.points.data(), n * sizeof(double2), stream);
  ctx.staging->upload(d_hull.get(), input.hull.sites.data(), d_hull.bytes(), stream);
  timer.end();

  timer.begin("bucket");
  EXPANSE_CUDA(cudaMemsetAsync(d_pred.get(), 0xff, d_pred.bytes(), stream));
  if (!input.hull.sites.empty())
    predecessor_kernel<<<grid_for(input.hull.sites.size()), 256, 0, stream>>>(
        d_hull.get(), static_cast<int>(input.hull.sites.size()), d_pred.get());
  DeviceArray<int> d_count(n, stream), d_offset(n + 1, stream);
  membership_count_kernel<<<grid_for(n), 256, 0, stream>>>(bl, d_points.get(), static_cast<int>(n), d_count.get());
  EXPANSE_CUDA(cudaGetLastError());
  std::size_t temp_bytes = 0;
  EXPANSE_CUDA(cub::DeviceScan::InclusiveSum(nullptr, temp_bytes, d_count.get(), d_offset.get() + 1, static_cast<int>(n), stream));
  {
    DeviceArray<unsigned char> temp(temp_bytes, stream);
    EXPANSE_CUDA(cudaMemsetAsync(d_offset.get(), 0, sizeof(int), stream));
    EXPANSE_CUDA(cub::DeviceScan::InclusiveSum(temp.get(), temp_bytes, d_count.get(), d_offset.get() + 1, static_cast<int>(n), stream));
  }
  int copies = 0;
  EXPANSE_CUDA(cudaMemcpyAsync(&copies, d_offset.get() + n, sizeof(int), cudaMemcpyDeviceToHost, stream));
  EXPANSE_CUDA(cudaStreamSynchronize(stream));
  const std::size_t m = static_cast<std::size_t>(copies);
  DeviceArray<std::uint32_t> d_keys(m, stream), d_keys_sorted(m, stream);
  DeviceArray<int> d_copy_sites(m, stream), d_sorted_sites(m, stream);
  membership_fill_kernel<<<grid_for(n), 256, 0, stream>>>(bl, d_points.get(), static_cast<int>(n), d_offset.get(),
                                                         d_keys.get(), d_copy_sites.get());
  EXPANSE_CUDA(cudaGetLastError());
  int key_bits = 1;
  while ((std::size_t{1} << key_bits) < cells + 1) ++key_bits;
  EXPANSE_CUDA(cub::DeviceRadixSort::SortPairs(nullptr, temp_bytes, d_keys.get(), d_keys_sorted.get(), d_copy_sites.get(),
                                               d_sorted_sites.get(), static_cast<int>(m), 0, key_bits, stream));
  {
    DeviceArray<unsigned char> temp(temp_bytes, stream);
    EXPANSE_CUDA(cub::DeviceRadixSort::SortPairs(temp.get(), temp_bytes, d_keys.get(), d_keys_sorted.get(),
                                                 d_copy_sites.get(), d_sorted_sites.get(), static_cast<int>(m), 0,
                                                 key_bits, stream));
  }
  DeviceArray<double2> d_copy_points(m, stream);
  DeviceArray<std::uint32_t> d_cell_start(cells + 1, stream);
  gather_kernel<<<grid_for(m), 256, 0, stream>>>(d_sorted_sites.get(), d_points.get(), static_cast<int>(m), d_copy_points.get());
  cell_start_kernel<<<grid_for(m), 256, 0, stream>>>(d_keys_sorted.get(), static_cast<int>(m), static_cast<int>(cells),
                                                          d_cell_start.get());
  DeviceArray<int> d_hash_cap(blocks, stream), d_list_cap(blocks, stream);
  DeviceArray<int> d_hash_offset(blocks + 1, stream), d_list_offset(blocks + 1, stream);
  block_sizes_kernel<<<grid_for(blocks), 256, 0, stream>>>(d_cell_start.get(), blocks, buckets * buckets,
                                                          d_hash_cap.get(), d_list_cap.get());
  EXPANSE_CUDA(cudaGetLastError());
  EXPANSE_CUDA(cub::DeviceScan::InclusiveSum(nullptr, temp_bytes, d_hash_cap.get(), d_hash_offset.get() + 1, blocks, stream));
  {
    DeviceArray<unsigned char> temp(temp_bytes, stream);
    EXPANSE_CUDA(cudaMemsetAsync(d_hash_offset.get(), 0, sizeof(int), stream));
    EXPANSE_CUDA(cudaMemsetAsync(d_list_offset.get(), 0, sizeof(int), stream));
    EXPANSE_CUDA(cub::DeviceScan::InclusiveSum(temp.get(), temp_bytes, d_hash_cap.get(), d_hash_offset.get() + 1, blocks, stream));
    EXPANSE_CUDA(cub::DeviceScan::InclusiveSum(temp.get(), temp_bytes, d_list_cap.get(), d_list_offset.get() + 1, blocks, stream));
  }
  int totals[2] = {0, 0};
  EXPANSE_CUDA(cudaMemcpyAsync(&totals[0], d_hash_offset.get() + blocks, sizeof(int), cudaMemcpyDeviceToHost, stream));
  EXPANSE_CUDA(cudaMemcpyAsync(&totals[1], d_list_offset.get() + blocks, sizeof(int), cudaMemcpyDeviceToHost, stream));
  EXPANSE_CUDA(cudaStreamSynchronize(stream));
  DeviceArray<unsigned long long> d_done(static_cast<std::size_t>(totals[0]), stream);
  DeviceArray<int2> d_list_a(static_cast<std::size_t>(totals[1]), stream), d_list_b(static_cast<std::size_t>(totals[1]), stream);
  DeviceArray<int> d_count_a(blocks, stream), d_count_b(blocks, stream), d_total(1, stream);
  DeviceArray<int> d_triangles(3 * (2 * n), stream);
  DeviceArray<unsigned int> d_counters(4, stream);
  EXPANSE_CUDA(cudaMemsetAsync(d_done.get(), 0xff, d_done.bytes(), stream));
  EXPANSE_CUDA(cudaMemsetAsync(d_count_a.get(), 0, d_count_a.bytes(), stream));
  EXPANSE_CUDA(cudaMemsetAsync(d_count_b.get(), 0, d_count_b.bytes(), stream));
  EXPANSE_CUDA(cudaMemsetAsync(d_counters.get(), 0, d_counters.bytes(), stream));
  timer.end();

  BlockState s{};
  s.bl = bl;
  s.cell_start = d_cell_start.get();
  s.points = d_copy_points.get();
  s.sites = d_sorted_sites.get();
  s.pred = d_pred.get();
  s.site_points = d_points.get();
  s.hash_offset = d_hash_offset.get();
  s.hash_cap = d_hash_cap.get();
  s.done = d_done.get();
  s.list_offset = d_list_offset.get();
  s.list_cap = d_list_cap.get();
  s.triangles = d_triangles.get();
  s.triangle_capacity = static_cast<unsigned>(2 * n);
  s.counters = d_counters.get();
  // Seeds write the first active lists into "next"; each iteration swaps.
  s.current = d_list_b.get();
  s.current_count = d_count_b.get();
  s.next = d_list_a.get();
  s.next_count = d_count_a.get();
  timer.begin("seeds");
  seed_kernel<<<blocks, 256, 0, stream>>>(s);
  EXPANSE_CUDA(cudaGetLastError());
  timer.end();

  timer.begin("front iterations");
  std::size_t iterations = 0;
  int* pinned_total = nullptr;
  EXPANSE_CUDA(cudaHostAlloc(reinterpret_cast<void**>(&pinned_total), sizeof(int), cudaHostAllocDefault));
  try {
    for (;;) {
      std::swap(s.current, s.next);
      std::swap(s.current_count, s.next_count);
      sum_kernel<<<1, 1024, 0, stream>>>(s.current_count, s.list_cap, blocks, d_total.get());
      EXPANSE_CUDA(cudaGetLastError());
      // The one host synchronisation per iteration: is the front empty?
      EXPANSE_CUDA(cudaMemcpyAsync(pinned_total, d_total.get(), sizeof(int), cudaMemcpyDeviceToHost, stream));
      EXPANSE_CUDA(cudaStreamSynchronize(stream));
      if (*pinned_total == 0) break;
      ++iterations;
      EXPANSE_CUDA(cudaMemsetAsync(s.next_count, 0, blocks * sizeof(int), stream));
      expand_kernel<<<blocks, threads, 0, stream>>>(s);
      EXPANSE_CUDA(cudaGetLastError());
      if (iterations > 4 * n + 16)
        throw Error(ErrorCode::internal, "CUDA paper layout: the front did not empty");
    }
  } catch (...) {
    cudaFreeHost(pinned_total);
    throw;
  }
  EXPANSE_CUDA(cudaFreeHost(pinned_total));
  timer.end();

  unsigned int counters[4] = {0, 0, 0, 0};
  EXPANSE_CUDA(cudaMemcpyAsync(counters, d_counters.get(), sizeof(counters), cudaMemcpyDeviceToHost, stream));
  EXPANSE_CUDA(cudaStreamSynchronize(stream));
  const std::size_t triangle_count = std::min<std::size_t>(counters[0], 2 * n);
  auto& partial = result.partial;
  partial.triangles.resize(triangle_count);
  timer.begin("download");
  ctx.staging->download(partial.triangles.data(), d_triangles.get(), triangle_count * 3 * sizeof(int), stream);
  timer.end();
  const double host_ms = ms_since(host_start);
  partial.deferred_expansions = counters[1];
  result.iterations = iterations;
  result.device_stages = timer.collect();
  result.host_stages.push_back({"cuda paper layout (host)", host_ms});
  RunCounters& rc = last_run_counters();
  rc = {};
  std::uint64_t predicates = 0;
  std::memcpy(&predicates, &counters[2], sizeof predicates);
  rc.predicates = predicates;
  rc.bytes_to_device = n * sizeof(double2) + d_hull.bytes();
  rc.bytes_to_host = triangle_count * 3 * sizeof(int) + iterations * sizeof(int);
  rc.triangles = triangle_count;
}

}  // namespace expanse::detail::cuda
