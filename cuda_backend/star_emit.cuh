#pragma once
// The star layout's output on the device: the triangles and their neighbours from the stars
// (emit), and the host audit's checks run where the adjacency is made (audit), with the open
// edges that deferred sites leave paired up. Included by star_kernels.cu alone.
#include <cstdint>

#include "star_common.cuh"
#include "star_view.cuh"

namespace expanse::detail::cuda {
namespace {

// The emit (scan's offsets -> triangles and neighbours) in two kernels, a thread per site and
// then a thread per triangle: one thread a site, linking each of its triangles by searching the
// stars around it, ran at 5.7 of a warp's 32 threads and took 7.0 ms at 4096^2 uniform under
// ncu (H100), its loops as uneven as the stars. Both read stars through
// StarView (star_view.cuh).

/// Blocks of kEmitSites sites for the triangles' kernel: a block's triangles are one contiguous
/// range of the output (offset[first] to offset[last]), staged in shared memory kEmitRoom at a
/// time and written in whole sectors (written by their sites, a thread's ~2 triangles at a time,
/// each 4-byte store was a sector of its own: 97 M sectors through L2 for 400 MB of triangles,
/// 17 M staged). Staged, and reading the stars through StarView, the kernel takes 0.80 ms
/// instead of 1.67 (ncu, 4096^2 uniform, H100).
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
/// is that site's owned bits, with no search of its owner's star.
__global__ void __launch_bounds__(128) emit_neighbors_kernel(const int* star, const std::uint32_t* info,
                                                             const int* offset, const std::uint32_t* owned,
                                                             const int* triangles, const int* rank, int n,
                                                             int capacity, int* neighbors) {
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
      across_ab = owned_triangle_index(offset, owned, a, q);
    }
  } else if (!star_deferred(ib)) {
    const StarView at_b(star, ib, b);
    const int q = at_b.find(a);  // (b, a, r) is b's triangle q
    if (q >= 0 && (q < at_b.degree() - 1 || at_b.closed())) {
      r = at_b.at(q + 1);
      across_ab = owned_triangle_index(offset, owned, b, q);
    }
  }
  if (r >= 0 && across_ab < 0) across_ab = triangle_index(star, info, offset, owned, b, a, r);
  int across_bi = -1;  // opposite a: (i, b, next), i's triangle t + 1
  if (closed || t + 2 < deg) {
    across_bi = owned_triangle_index(offset, owned, i, t + 1 < deg ? t + 1 : 0);
    if (across_bi < 0) across_bi = triangle_index(star, info, offset, owned, i, b, own.at(t + 2));
  }
  int across_ia = -1;  // opposite b: (i, previous, a), i's triangle t - 1
  if (closed || t >= 1) {
    across_ia = owned_triangle_index(offset, owned, i, t >= 1 ? t - 1 : deg - 1);
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

}  // namespace
}  // namespace expanse::detail::cuda
