// The raw input prepared on the device, as prepare_sites does it on the host: scaled by the
// power of two the host's scan chose, duplicates merged (the smallest input index represents
// each group), the sites put in Morton order; then grown by the per-site layout.
//
//   upload raw points -> Morton codes of the scaled points -> sort (stable: input order within a
//     key; by the codes' top 32 bits where a sample says they nearly tell the points apart,
//     each run of equal keys then ordered by the whole code; else by the codes refined by where
//     in its quantum a point lies, refined_morton) -> gather the scaled points
//     -> merge: a point equal to an earlier one of its run of equal codes joins that one's group
//     -> compact the groups' first points: the sites, already in Morton order (and, where points
//        repeat, every input's representative)
//     -> download the sites, their input indices, the representatives and the hull's site ids
//     -> grow_per_site on the sites already on the device
//
// On the host this took 125-170 ms at 4096^2 on 16 threads (the H100's host): the
// sorting and merging is the device's to do, and the host only validates and finds the hull.
// Equal points have equal codes, so merging looks only through runs of equal codes (30 bits a
// coordinate: distinct points share one only when closer than 2^-30 of the box). Where a run is
// longer than kLookBackLimit (many copies of few points, or a cluster far finer than the
// quantisation), equal points are found through hash tables, one for each run of equal codes,
// instead (three more sorts, by y, x and the code, had made kuzmin's merge 11.9 ms against
// uniform's 2.8 at 4096^2 on the H100). (A first version merged within cells of the star grid
// and left crowded cells to the host: a quantile grid's central cell holds far more than its
// share of a radial cluster, so kuzmin inputs went back to the host's preparation.)
#include <cub/device/device_radix_sort.cuh>
#include <cub/device/device_scan.cuh>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <future>
#include <optional>
#include <ranges>

#include "cuda_internal.hpp"
#include "support/timing.hpp"
#include "input/morton.hpp"
#include "input/parallel.hpp"
#include "star_grid.hpp"

namespace expanse::detail::cuda {
namespace {

/// Past this many points with one Morton code (the full sort's, refined_morton), equal points are
/// found through hash tables, not by looking back through the run. Kuzmin's centre at 4096^2 has
/// runs of up to 164 sites (21% of its sites in runs of 65 to 164), where a look back costs less
/// than the tables' four passes and their atomics (a limit of 64 sent kuzmin through the tables:
/// 0.83 ms for the merge, H100).
constexpr int kLookBackLimit = 256;
/// Past this many points with one Morton code the run is "unordered": the device's preparation
/// leaves it in input order, and the walks order such inputs' cells by x (StarGrid's
/// `unordered_runs`). Kuzmin has them from 2048^2 up.
constexpr int kUnorderedRunLimit = 64;
static_assert(kUnorderedRunLimit <= kLookBackLimit);
constexpr int kThreads = 256;
int blocks_for(std::size_t n) { return static_cast<int>((n + kThreads - 1) / kThreads); }

/// p * 2^e, exact: as InputScan::scaled (a multiplication by `factor`, or scalbn past 2^1023).
/// Applied where the raw points are read (codes, gather, hull), not in a pass of its own: one
/// read and one write of every point fewer (268 MB each at 4096^2).
struct InputScale {
  int e;
  double factor;

  __device__ __forceinline__ double2 operator()(double2 p) const {
    if (e <= 1023) return make_double2(__dmul_rn(p.x, factor), __dmul_rn(p.y, factor));
    return make_double2(scalbn(p.x, e), scalbn(p.y, e));
  }
};

/// The scaled points in sorted order.
__global__ void gather_scaled_kernel(const int* sorted_ids, const double2* raw, InputScale scale, int n,
                                     double2* sorted) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i < n) sorted[i] = scale(raw[sorted_ids[i]]);
}

/// What first_equal_kernel's survey finds (bits of one word).
constexpr unsigned int kSomeRepeat = 1u;    ///< some point repeats one earlier in its run
constexpr unsigned int kUnorderedRun = 2u;  ///< a run longer than kUnorderedRunLimit + 1
constexpr unsigned int kTooLongRun = 4u;    ///< a run longer than kLookBackLimit + 1: the hash tables

static_assert(kThreads % 32 == 0, "first_equal_kernel's warps fill their blocks");

/// 32 bits of v that equal points share (-0 as +0). Points of one run lie within one quantum, so
/// their coordinates differ in the low bits: those are kept whole.
__device__ __forceinline__ unsigned int point_tag(double2 v) {
  const auto x = static_cast<unsigned long long>(__double_as_longlong(v.x == 0.0 ? 0.0 : v.x));
  const auto y = static_cast<unsigned long long>(__double_as_longlong(v.y == 0.0 ? 0.0 : v.y));
  return static_cast<unsigned int>(x) ^ (static_cast<unsigned int>(y) * 0x9E3779B9u) ^
         static_cast<unsigned int>((x ^ y) >> 32);
}

/// Bits lo .. hi - 1 of a word (none where hi <= lo; lo and hi clamped to 0 .. 32).
__device__ __forceinline__ unsigned int bits_between(int lo, int hi) {
  lo = max(lo, 0);
  hi = min(hi, 32);
  if (hi <= lo) return 0u;
  const unsigned int below_hi = hi == 32 ? ~0u : (1u << hi) - 1u;
  return below_hi & ~((1u << lo) - 1u);
}

/// first[p]: the first position of p's run of equal Morton codes holding a point equal to p's
/// (p itself if none); head[p] = 1 where that is p. Equal points have equal codes, and within a
/// run the positions are in input order (the sort is stable), so the first is the smallest input
/// index. Only where the survey found no run longer than kLookBackLimit + 1.
///
/// A warp looks back together: its lanes are consecutive positions, and it goes through the
/// positions from the start of its first lane's run to its last lane 32 at a time, each lane
/// reading one and passing the point's tag (point_tag) around; a lane reads a point to compare it
/// with its own only where their tags agree. Points read whole by every lane were bound by the
/// first-level cache's bandwidth (16 bytes to each of 32 lanes a step, as much as 32 lanes
/// reading 16 bytes each): kuzmin 4096^2's survey took 0.53 ms with a look back a lane, 0.51
/// with one point a step for the warp, 0.34 with the tags (H100, ncu;
/// 22.6 M steps).
///
/// With `survey` (first and head null) it only learns what the runs hold, into *survey's bits:
/// mostly no point repeats, and then every position is a head and no scan is needed. A warp with
/// a position further than kLookBackLimit into its run only flags the run as too long (one read
/// a lane), so a run of a million copies costs no more than the look backs near its start.
__global__ void first_equal_kernel(const double2* __restrict__ sorted, const std::uint64_t* __restrict__ codes, int n,
                                   int* first, int* head, unsigned int* survey) {
  const int p = blockIdx.x * blockDim.x + threadIdx.x;
  const int lane = threadIdx.x & 31;
  const int warp_first = p - lane;
  if (warp_first >= n) return;  // the whole warp
  const bool valid = p < n;
  const std::uint64_t code = valid ? codes[p] : 0;
  const bool starts = !valid || p == 0 || codes[p - 1] != code;
  if (survey) {
    const bool unordered = valid && p > kUnorderedRunLimit && codes[p - kUnorderedRunLimit - 1] == code;
    const bool too_long = valid && p > kLookBackLimit && codes[p - kLookBackLimit - 1] == code;
    const unsigned found =
        (__any_sync(~0u, unordered) ? kUnorderedRun : 0u) | (__any_sync(~0u, too_long) ? kTooLongRun : 0u);
    if (found & kTooLongRun) {
      if (lane == 0 && (*survey & found) != found) atomicOr(survey, found);
      return;
    }
    if (lane == 0 && found && (*survey & found) != found) atomicOr(survey, found);
  }
  // Each lane's run start: the last lane at or below it that starts a run, else the first lane's
  // run start before the warp.
  const unsigned starts_mask = __ballot_sync(~0u, starts);
  int q = p;
  if (starts_mask != ~0u) {  // some lane's run began before it
    int warp_begin = warp_first;
    if (!(starts_mask & 1u)) {
      // Back from the warp, 32 positions a step (at most kLookBackLimit + 1 in all).
      const std::uint64_t first_code = __shfl_sync(~0u, code, 0);
      for (int base = warp_first;; base -= 32) {
        const int at = base - 1 - lane;
        const unsigned other = __ballot_sync(~0u, at < 0 || codes[at] != first_code);
        if (other) {
          warp_begin = base - (__ffs(other) - 1);
          break;
        }
      }
    }
    const unsigned at_or_below = starts_mask & (lane == 31 ? ~0u : (2u << lane) - 1u);
    const int begin = at_or_below ? warp_first + 31 - __clz(at_or_below) : warp_begin;
    const int last = min(warp_first + 31, n - 1);
    const double2 v = valid ? sorted[p] : make_double2(0.0, 0.0);
    const unsigned int tag = point_tag(v);
    for (int base = warp_begin; base < last; base += 32) {
      const unsigned int tag_there = base + lane < last ? point_tag(sorted[base + lane]) : 0u;
      // Bit k: position base + k has this lane's tag (three instructions a position, unrolled).
      unsigned int agree = 0;
#pragma unroll
      for (int k = 0; k < 32; ++k) agree |= (__shfl_sync(~0u, tag_there, k) == tag ? 1u : 0u) << k;
      // Only positions of this lane's run before it; the first equal point found is the smallest.
      for (agree &= bits_between(begin - base, q - base); agree; agree &= agree - 1) {
        const int j = base + __ffs(agree) - 1;
        const double2 w = sorted[j];
        if (w.x == v.x && w.y == v.y) {
          q = j;
          break;
        }
      }
    }
  }
  if (survey) {
    if (__any_sync(~0u, q != p) && lane == 0 && (*survey & kSomeRepeat) == 0u) atomicOr(survey, kSomeRepeat);
    return;
  }
  if (!valid) return;
  first[p] = q;
  head[p] = q == p;
}

/// The heads become the sites, in Morton order: site slot[p] is the point at position p. Reads
/// and writes in order only: where points repeat, representative_kernel maps every input index
/// to its group's first (a scatter by input index, which cost 2.6 ms at 4096^2 on the H100 with
/// the input-to-site map beside it).
__global__ void compact_kernel(const double2* sorted, const int* sorted_input, const int* head, const int* slot, int n,
                               double2* site_points, int* site_input) {
  const int p = blockIdx.x * blockDim.x + threadIdx.x;
  if (p >= n || !head[p]) return;
  site_points[slot[p]] = sorted[p];
  site_input[slot[p]] = sorted_input[p];
}

/// Every input index gets its group's first input index (only needed where points repeat).
__global__ void representative_kernel(const int* sorted_input, const int* first, int n, int* representative) {
  const int p = blockIdx.x * blockDim.x + threadIdx.x;
  if (p >= n) return;
  representative[sorted_input[p]] = sorted_input[first[p]];
}

/// p's Morton code, as prepare_sites computes it (the same host-and-device code).
__device__ __forceinline__ std::uint64_t morton(double2 p, const Quantiser& q) {
  return morton_code(q.x(p.x), q.y(p.y));
}

/// The full sort's key: p's Morton code and, in the 4 bits below it that a 64-bit key leaves
/// free, where p lies within its quantum (2 bits a coordinate, interleaved as the code's). The
/// order it sorts the sites in is a Morton order still (the host's BucketTree takes equal codes
/// in any order), and equal points have equal keys. A cluster finer than the quantisation
/// (kuzmin's centre: thousands of sites a code at 4096^2) is then in sixteen runs a code, each
/// in input order, where it was in one: the merge's hash tables for each run took kuzmin 1.41 ->
/// 0.86 ms (H100), in the same 8 radix passes as the 60 bits alone. (Its
/// walks want more order than that: CellBuckets orders such sites within their cells.)
constexpr int kRefineBits = 2;
static_assert(2 * Quantiser::bits + 2 * kRefineBits <= 64);
__device__ __forceinline__ std::uint64_t refined_morton(double2 p, const Quantiser& q) {
  const std::uint32_t qx = q.x(p.x), qy = q.y(p.y);
  // The fraction of the quantum below p, as Quantiser computes the quantum (no contraction in
  // this file): monotone in the coordinate within a quantum.
  auto part = [](double v, double origin, double scale, std::uint32_t quantum) {
    const double t = ((v - origin) * scale - static_cast<double>(quantum)) * (1 << kRefineBits);
    return t > 0.0 ? (t < (1 << kRefineBits) ? static_cast<std::uint32_t>(t) : (1u << kRefineBits) - 1u) : 0u;
  };
  const std::uint32_t fx = part(p.x, q.origin_x, q.scale, qx), fy = part(p.y, q.origin_y, q.scale, qy);
  std::uint32_t fine = 0;
  for (int b = kRefineBits - 1; b >= 0; --b) fine = (fine << 2) | (((fy >> b) & 1u) << 1) | ((fx >> b) & 1u);
  return (morton_code(qx, qy) << (2 * kRefineBits)) | fine;
}

__global__ void morton_kernel(const double2* raw, InputScale scale, int n, Quantiser q, std::uint64_t* codes,
                              int* ids) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= n) return;
  codes[i] = refined_morton(scale(raw[i]), q);
  ids[i] = i;
}

/// The short sort: by the top 32 of the codes' 2 * Quantiser::bits bits (4 radix passes of 8 bytes
/// an element, where the whole code takes 8 of 12), then each run of equal keys ordered by its
/// whole codes. Where the sites are spread out, as uniform inputs, grids and gaussian clusters
/// are over their box, such runs are rare and short; a dense cluster in a wide box (kuzmin's
/// centre) puts millions of points in a few keys, and takes the full sort.
constexpr int kShortKeyShift = 2 * Quantiser::bits - 32;
/// The longest run of equal short keys a thread orders (an insertion sort by the whole code); a
/// longer run sends the input through the full sort. Not above kUnorderedRunLimit: runs of the
/// short sort's codes are never unordered nor too long to look back through.
constexpr int kShortRunLimit = 32;
static_assert(kShortRunLimit <= kUnorderedRunLimit);
/// Sampled points whose short keys forecast which sort serves (short_sort_forecast).
constexpr int kShortKeySamples = 4096;

__global__ void short_key_kernel(const double2* raw, InputScale scale, int n, Quantiser q, std::uint32_t* keys,
                                 int* ids) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= n) return;
  keys[i] = static_cast<std::uint32_t>(morton(scale(raw[i]), q) >> kShortKeyShift);
  ids[i] = i;
}

/// flags[0] = 1 where a run of equal short keys (sorted) is longer than kShortRunLimit.
__global__ void short_run_check_kernel(const std::uint32_t* keys, int n, unsigned int* flags) {
  const int p = blockIdx.x * blockDim.x + threadIdx.x;
  if (p >= kShortRunLimit && p < n && keys[p - kShortRunLimit] == keys[p]) atomicOr(flags, 1u);
}

/// Each run of equal short keys (at most kShortRunLimit long) ordered by (whole code, input
/// index), as the full sort orders it: a thread per run, from its first position. The short sort
/// is stable, so a run's input indices ascend, and an insertion sort keeps them so among equal
/// codes.
__global__ void short_run_order_kernel(const std::uint32_t* keys, const double2* raw, InputScale scale, Quantiser q,
                                       int n, int* sorted_ids) {
  const int p = blockIdx.x * blockDim.x + threadIdx.x;
  if (p + 1 >= n || keys[p + 1] != keys[p] || (p > 0 && keys[p - 1] == keys[p])) return;
  int end = p + 2;
  while (end < n && keys[end] == keys[p]) ++end;
  std::uint64_t codes[kShortRunLimit];
  int ids[kShortRunLimit];
  const int length = end - p;
  for (int k = 0; k < length; ++k) {
    const int id = sorted_ids[p + k];
    const std::uint64_t code = morton(scale(raw[id]), q);
    int j = k;
    for (; j > 0 && codes[j - 1] > code; --j) {
      codes[j] = codes[j - 1];
      ids[j] = ids[j - 1];
    }
    codes[j] = code;
    ids[j] = id;
  }
  for (int k = 0; k < length; ++k) sorted_ids[p + k] = ids[k];
}

/// The scaled points in sorted order, and their codes (the short sort sorted only keys).
__global__ void gather_scaled_codes_kernel(const int* sorted_ids, const double2* raw, InputScale scale, Quantiser q,
                                           int n, double2* sorted, std::uint64_t* codes) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= n) return;
  const double2 p = scale(raw[sorted_ids[i]]);
  sorted[i] = p;
  codes[i] = morton(p, q);
}

/// Whether the short sort should serve these points: among kShortKeySamples of them, one from each
/// of as many equal stretches of the input, at most one in 64 shares its short key with another.
/// A dense cluster in a wide box shares keys wholesale (kuzmin 20,000: most of the sample), an
/// even spread almost never (uniform 4096^2: two of 4096 with odds of about 1 in 500). Only a
/// forecast: the device checks the runs after the sort, and a long one still takes the full sort.
/// Tuning::morton_sort full or short_keys decides instead (short: no forecast, the check stays).
bool short_sort_forecast(std::span<const Point2> points, const InputScan& scan, const Quantiser& q,
                         Tuning::MortonSort sort) {
  if (sort == Tuning::MortonSort::full) return false;
  if (sort == Tuning::MortonSort::short_keys) return true;
  const std::size_t n = points.size();
  const std::size_t samples = std::min<std::size_t>(n, kShortKeySamples);
  if (samples == 0) return true;
  std::vector<std::uint32_t> keys(samples);
  for (std::size_t i = 0; i < samples; ++i) {
    // Stretch i of the input, [i n / samples, (i + 1) n / samples), at a hashed offset: distinct
    // points, and ordered inputs (row-major grids) do not alias.
    const std::size_t begin = i * n / samples, length = (i + 1) * n / samples - begin;
    const std::size_t at = begin + static_cast<std::size_t>(mix_bits(i) % length);
    const Point2 p = scan.scaled(points[at]);
    keys[i] = static_cast<std::uint32_t>(morton_code(q.x(p.x), q.y(p.y)) >> kShortKeyShift);
  }
  std::sort(keys.begin(), keys.end());
  std::size_t shared = 0;
  for (std::size_t i = 0; i < samples; ++i)
    shared += (i > 0 && keys[i - 1] == keys[i]) || (i + 1 < samples && keys[i + 1] == keys[i]);
  return shared * 64 <= samples;
}

/// The hash table's empty slot (cudaMemset's 0x7f bytes): above every position (n < 2^30).
constexpr int kEmptySlot = 0x7f7f7f7f;

/// A hash of point v; -0 hashes as +0 (the two are equal points).
__device__ __forceinline__ std::uint64_t point_hash(double2 v) {
  std::uint64_t z = static_cast<std::uint64_t>(__double_as_longlong(v.x == 0.0 ? 0.0 : v.x));
  z ^= static_cast<std::uint64_t>(__double_as_longlong(v.y == 0.0 ? 0.0 : v.y)) * 0x9E3779B97F4A7C15ull;
  return mix_bits(z);
}

/// key[p] = p where a run of equal codes starts, 0 elsewhere: their running maximum is every
/// position's run start.
__global__ void run_start_key_kernel(const std::uint64_t* codes, int n, int* key) {
  const int p = blockIdx.x * blockDim.x + threadIdx.x;
  if (p < n) key[p] = (p == 0 || codes[p - 1] != codes[p]) ? p : 0;
}

struct MaximumOp {
  __device__ __forceinline__ int operator()(int a, int b) const { return a > b ? a : b; }
};

/// length[s] = the length of the run that starts at s, written by its last position.
__global__ void run_length_kernel(const std::uint64_t* codes, const int* start, int n, int* length) {
  const int p = blockIdx.x * blockDim.x + threadIdx.x;
  if (p < n && (p == n - 1 || codes[p + 1] != codes[p])) length[start[p]] = p - start[p] + 1;
}

/// Where runs of equal codes are too long to search pairwise. Equal points have equal codes, so
/// they lie in one run, and each run has a table of its own: twice its length, from slot twice
/// its start (a table of 2n slots in all, at most half full). A warp's positions lie in one or
/// a few runs, so its probes stay in a few kilobytes, where one table over all points had sent
/// every probe to a random line of 128 MB (kuzmin 4096^2: 3.2 ms for the merge, H100).
/// Every position p enters its run's table (linear probing) under its point. A slot holds
/// positions of one point only and ends at the smallest of them (atomicMin among equal points):
/// the first in the stable sort, the smallest input index.
struct RunTables {
  int* table;
  const int* start;   ///< each position's run start
  const int* length;  ///< at each run start, the run's length

  /// p's first probe and its run's table (`size` slots from `base`).
  __device__ __forceinline__ unsigned first_probe(int p, double2 v, int* base, unsigned* size) const {
    const int s = start[p];
    *size = 2u * static_cast<unsigned>(length[s]);
    *base = 2 * s;
    const std::uint64_t z = point_hash(v);
    return (static_cast<std::uint32_t>(z) ^ static_cast<std::uint32_t>(z >> 32)) % *size;
  }
};

/// *repeats = 1 where some point repeats.
__global__ void hash_insert_kernel(const double2* sorted, int n, RunTables runs, unsigned int* repeats) {
  const int p = blockIdx.x * blockDim.x + threadIdx.x;
  if (p >= n) return;
  const double2 v = sorted[p];
  int base;
  unsigned size;
  for (unsigned h = runs.first_probe(p, v, &base, &size);; h = h + 1 == size ? 0 : h + 1) {
    int* slot = runs.table + base + h;
    int s = *slot;
    if (s == kEmptySlot) {
      s = atomicCAS(slot, kEmptySlot, p);
      if (s == kEmptySlot) return;
    }
    const double2 w = sorted[s];  // a slot's point never changes, only its smallest position
    if (w.x == v.x && w.y == v.y) {
      atomicMin(slot, p);
      if (*repeats == 0u) atomicOr(repeats, 1u);
      return;
    }
  }
}

/// After hash_insert_kernel: first[p] = the first position of p's point; head[p] = 1 where
/// that is p.
__global__ void hash_first_kernel(const double2* sorted, int n, RunTables runs, int* first, int* head) {
  const int p = blockIdx.x * blockDim.x + threadIdx.x;
  if (p >= n) return;
  const double2 v = sorted[p];
  int base;
  unsigned size;
  for (unsigned h = runs.first_probe(p, v, &base, &size);; h = h + 1 == size ? 0 : h + 1) {
    const int s = runs.table[base + h];
    const double2 w = sorted[s];
    if (w.x == v.x && w.y == v.y) {
      first[p] = s;
      head[p] = s == p;
      return;
    }
  }
}

/// The hull's input indices -> site ids. Input x lies at the position of the sort whose code is
/// x's and whose input index is x: the sort is stable, so within a run of equal codes the input
/// indices ascend, and two binary searches find it (h of them, where an input-to-site map
/// written for every point had cost a scatter of n). first and slot null: no point repeats, and
/// the positions are the site ids. `refined`: the codes are the full sort's keys (refined_morton).
__global__ void hull_sites_kernel(const int* hull_input, int h, const double2* raw, InputScale scale, Quantiser q,
                                  bool refined, const std::uint64_t* codes, const int* sorted_input, int n,
                                  const int* first, const int* slot, int* hull_sites) {
  const int t = blockIdx.x * blockDim.x + threadIdx.x;
  if (t >= h) return;
  const int x = hull_input[t];
  const std::uint64_t code = refined ? refined_morton(scale(raw[x]), q) : morton(scale(raw[x]), q);
  int lo = 0, hi = n;  // the first position whose (code, input) is not below (code, x)
  while (lo < hi) {
    const int mid = lo + (hi - lo) / 2;
    const std::uint64_t c = codes[mid];
    if (c < code || (c == code && sorted_input[mid] < x))
      lo = mid + 1;
    else
      hi = mid;
  }
  hull_sites[t] = first ? slot[first[lo]] : lo;
}

}  // namespace

bool grow_per_site_from_input(Context& ctx, const InputGrowInput& input, InputGrowResult& result) {
  const cudaStream_t stream = ctx.stream;
  const std::size_t n = input.points.size();
  if (n >= (std::size_t{1} << 30)) return false;  // the host's path refuses it, with the error
  const Box& bounds = input.scan.bounds;
  // Raw, sorted and site points; codes twice; ids twice, the merge's three arrays, the sites'
  // input indices and the representatives.
  require_device_memory(n * (3 * sizeof(double2) + 2 * sizeof(std::uint64_t) + 7 * sizeof(int)), n, "points");

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
  const auto host_start = Clock::now();
  std::size_t m = 0;
  DeviceArray<double2> d_site_points(n, stream);
  DeviceArray<int> d_site_input(n, stream), d_representative(n, stream);
  std::optional<DeviceArray<int>> d_hull_sites;  // once the hull is known
  bool short_sorted = false;                     // the sites ordered by the short sort
  bool long_runs = false;                        // runs of equal codes past kUnorderedRunLimit
  bool hashed = false;                           // runs past kLookBackLimit: the hash tables
  // Before the device's first stage: the forecast is host work, and timed inside a stage it
  // would count as the device's.
  const bool short_forecast = short_sort_forecast(input.points, input.scan, Quantiser(bounds),
                                                       tuning_from_environment().morton_sort);
  std::size_t h = 0;
  Clock::time_point host_uploaded;
  double hull_wait_ms = 0.0;
  {
    DeviceArray<double2> d_raw(n, stream), d_sorted(n, stream);
    timer.begin("upload");
    static_assert(sizeof(Point2) == sizeof(double2));
    ctx.staging->upload(d_raw.get(), input.points.data(), n * sizeof(double2), stream);
    timer.end();
    host_uploaded = Clock::now();

    DeviceArray<std::uint64_t> d_codes(n, stream), d_codes_sorted(n, stream);
    DeviceArray<int> d_ids(n, stream), d_sorted_ids(n, stream);
    DeviceArray<int> d_first(n, stream), d_head(n, stream), d_slot(n, stream);
    // [0]: the short sort's check (short keys' runs too long), then the merge's survey
    // (first_equal_kernel's bits); [1]: some point repeats (the hash tables).
    DeviceArray<unsigned int> d_flags(2, stream);
    // The short sort's keys live in the codes' array, unsorted then sorted (2n words).
    std::uint32_t* const d_keys = reinterpret_cast<std::uint32_t*>(d_codes.get());
    std::uint32_t* const d_keys_sorted = d_keys + n;
    std::size_t sort_bytes = 0, short_bytes = 0, scan_bytes = 0, max_bytes = 0;
    EXPANSE_CUDA(cub::DeviceRadixSort::SortPairs(nullptr, sort_bytes, d_codes.get(), d_codes_sorted.get(), d_ids.get(),
                                                 d_sorted_ids.get(), static_cast<int>(n), 0,
                                                 2 * Quantiser::bits + 2 * kRefineBits, stream));
    EXPANSE_CUDA(cub::DeviceRadixSort::SortPairs(nullptr, short_bytes, d_keys, d_keys_sorted, d_ids.get(),
                                                 d_sorted_ids.get(), static_cast<int>(n), 0, 32, stream));
    EXPANSE_CUDA(cub::DeviceScan::ExclusiveSum(nullptr, scan_bytes, d_head.get(), d_slot.get(), static_cast<int>(n),
                                               stream));
    EXPANSE_CUDA(cub::DeviceScan::InclusiveScan(nullptr, max_bytes, d_first.get(), d_slot.get(), MaximumOp{},
                                                static_cast<int>(n), stream));
    DeviceArray<unsigned char> d_temp(std::max({sort_bytes, short_bytes, scan_bytes, max_bytes}), stream);

    // The sites' order: Morton codes as prepare_sites and the seam's bucket tree compute them.
    timer.begin("sort");
    const InputScale scale{input.scan.scale_exponent, input.scan.factor};
    const Quantiser quantiser(bounds);
    unsigned int* const words = ctx.pinned_words;
    std::size_t temp_bytes = d_temp.bytes();
    // The short sort where the forecast allows and no run of equal keys turns out too long; the
    // check's read-back takes the place of the merge's (whose long runs it rules out).
    if (short_forecast) {
      short_key_kernel<<<blocks_for(n), kThreads, 0, stream>>>(d_raw.get(), scale, static_cast<int>(n), quantiser,
                                                               d_keys, d_ids.get());
      EXPANSE_CUDA(cudaGetLastError());
      EXPANSE_CUDA(cub::DeviceRadixSort::SortPairs(d_temp.get(), temp_bytes, d_keys, d_keys_sorted, d_ids.get(),
                                                   d_sorted_ids.get(), static_cast<int>(n), 0, 32, stream));
      EXPANSE_CUDA(cudaMemsetAsync(d_flags.get(), 0, sizeof(unsigned int), stream));
      short_run_check_kernel<<<blocks_for(n), kThreads, 0, stream>>>(d_keys_sorted, static_cast<int>(n), d_flags.get());
      EXPANSE_CUDA(cudaGetLastError());
      EXPANSE_CUDA(cudaMemcpyAsync(&words[0], d_flags.get(), sizeof(unsigned int), cudaMemcpyDeviceToHost, stream));
      EXPANSE_CUDA(cudaStreamSynchronize(stream));
      short_sorted = words[0] == 0;
      if (short_sorted) {
        short_run_order_kernel<<<blocks_for(n), kThreads, 0, stream>>>(d_keys_sorted, d_raw.get(), scale, quantiser,
                                                                       static_cast<int>(n), d_sorted_ids.get());
        gather_scaled_codes_kernel<<<blocks_for(n), kThreads, 0, stream>>>(
            d_sorted_ids.get(), d_raw.get(), scale, quantiser, static_cast<int>(n), d_sorted.get(), d_codes_sorted.get());
        EXPANSE_CUDA(cudaGetLastError());
      }
    }
    if (!short_sorted) {
      morton_kernel<<<blocks_for(n), kThreads, 0, stream>>>(d_raw.get(), scale, static_cast<int>(n), quantiser,
                                                            d_codes.get(), d_ids.get());
      EXPANSE_CUDA(cudaGetLastError());
      temp_bytes = d_temp.bytes();
      EXPANSE_CUDA(cub::DeviceRadixSort::SortPairs(d_temp.get(), temp_bytes, d_codes.get(), d_codes_sorted.get(),
                                                   d_ids.get(), d_sorted_ids.get(), static_cast<int>(n), 0,
                                                   2 * Quantiser::bits + 2 * kRefineBits, stream));
      gather_scaled_kernel<<<blocks_for(n), kThreads, 0, stream>>>(d_sorted_ids.get(), d_raw.get(), scale,
                                                                   static_cast<int>(n), d_sorted.get());
      EXPANSE_CUDA(cudaGetLastError());
    }
    timer.end();

    timer.begin("merge duplicates");
    // First a survey of the runs: whether any point repeats (where none does, no groups and no
    // scan: H100, 4096^2, the merge 0.17 -> 0.07 ms on uniform, gaussian and the lattice),
    // whether a run is unordered, whether one is too long to look back through.
    EXPANSE_CUDA(cudaMemsetAsync(d_flags.get(), 0, 2 * sizeof(unsigned int), stream));
    first_equal_kernel<<<blocks_for(n), kThreads, 0, stream>>>(d_sorted.get(), d_codes_sorted.get(),
                                                               static_cast<int>(n), nullptr, nullptr, d_flags.get());
    EXPANSE_CUDA(cudaGetLastError());
    EXPANSE_CUDA(cudaMemcpyAsync(&words[0], d_flags.get(), sizeof(unsigned int), cudaMemcpyDeviceToHost, stream));
    EXPANSE_CUDA(cudaStreamSynchronize(stream));
    const unsigned int survey = words[0];
    long_runs = (survey & kUnorderedRun) != 0;
    hashed = (survey & kTooLongRun) != 0;
    words[3] = survey & kSomeRepeat;
    RunTables runs{};
    if (hashed) {
      // A run of equal codes too long to search pairwise (many copies of a point, or a cluster
      // far finer than the quantisation): equal points found through a hash table for each run.
      // The unsorted codes and ids are free now: the tables (2n slots) go to the codes' array
      // (one array fewer from the pool), the runs' lengths to the ids', their starts to the
      // slots' (free until the scan below).
      int* const run_start = d_slot.get();
      int* const run_length = d_ids.get();
      int* const tables = reinterpret_cast<int*>(d_codes.get());
      static_assert(sizeof(std::uint64_t) == 2 * sizeof(int));
      run_start_key_kernel<<<blocks_for(n), kThreads, 0, stream>>>(d_codes_sorted.get(), static_cast<int>(n),
                                                                   d_first.get());
      std::size_t max_bytes = d_temp.bytes();
      EXPANSE_CUDA(cub::DeviceScan::InclusiveScan(d_temp.get(), max_bytes, d_first.get(), run_start, MaximumOp{},
                                                  static_cast<int>(n), stream));
      run_length_kernel<<<blocks_for(n), kThreads, 0, stream>>>(d_codes_sorted.get(), run_start, static_cast<int>(n),
                                                                run_length);
      EXPANSE_CUDA(cudaMemsetAsync(tables, 0x7f, 2 * n * sizeof(int), stream));
      runs = RunTables{tables, run_start, run_length};
      hash_insert_kernel<<<blocks_for(n), kThreads, 0, stream>>>(d_sorted.get(), static_cast<int>(n), runs,
                                                                 d_flags.get() + 1);
      EXPANSE_CUDA(cudaGetLastError());
      EXPANSE_CUDA(cudaMemcpyAsync(&words[3], d_flags.get() + 1, sizeof(unsigned int), cudaMemcpyDeviceToHost, stream));
      EXPANSE_CUDA(cudaStreamSynchronize(stream));
    }
    const bool repeats = words[3] != 0;
    if (repeats) {
      if (!hashed)
        first_equal_kernel<<<blocks_for(n), kThreads, 0, stream>>>(d_sorted.get(), d_codes_sorted.get(),
                                                                   static_cast<int>(n), d_first.get(), d_head.get(),
                                                                   nullptr);
      else
        hash_first_kernel<<<blocks_for(n), kThreads, 0, stream>>>(d_sorted.get(), static_cast<int>(n), runs,
                                                                  d_first.get(), d_head.get());
      EXPANSE_CUDA(cudaGetLastError());
      temp_bytes = d_temp.bytes();
      EXPANSE_CUDA(cub::DeviceScan::ExclusiveSum(d_temp.get(), temp_bytes, d_head.get(), d_slot.get(),
                                                 static_cast<int>(n), stream));
      // How many sites: the last slot plus the last head.
      EXPANSE_CUDA(cudaMemcpyAsync(&words[1], d_slot.get() + n - 1, sizeof(int), cudaMemcpyDeviceToHost, stream));
      EXPANSE_CUDA(cudaMemcpyAsync(&words[2], d_head.get() + n - 1, sizeof(int), cudaMemcpyDeviceToHost, stream));
    }
    timer.end();
    // The hull, which the host has been finding meanwhile, in site ids.
    const auto host_hull_wait = Clock::now();
    const std::vector<std::int32_t>* hull_input = input.hull();
    hull_wait_ms = ms_since(host_hull_wait);
    if (!hull_input) return false;  // collinear: the host's path handles it
    h = hull_input->size();
    DeviceArray<int> d_hull_input(h, stream);
    d_hull_sites.emplace(h, stream);
    ctx.staging->upload(d_hull_input.get(), hull_input->data(), h * sizeof(int), stream);
    hull_sites_kernel<<<blocks_for(h), kThreads, 0, stream>>>(
        d_hull_input.get(), static_cast<int>(h), d_raw.get(), scale, quantiser, !short_sorted, d_codes_sorted.get(),
        d_sorted_ids.get(),
        static_cast<int>(n), repeats ? d_first.get() : nullptr, repeats ? d_slot.get() : nullptr,
        d_hull_sites->get());
    EXPANSE_CUDA(cudaGetLastError());
    EXPANSE_CUDA(cudaStreamSynchronize(stream));
    m = repeats ? static_cast<std::size_t>(words[1]) + words[2] : n;
    if (m < n) {  // points repeat: the sites are the groups' first points; every input's representative
      timer.begin("compact");
      compact_kernel<<<blocks_for(n), kThreads, 0, stream>>>(d_sorted.get(), d_sorted_ids.get(), d_head.get(),
                                                             d_slot.get(), static_cast<int>(n), d_site_points.get(),
                                                             d_site_input.get());
      representative_kernel<<<blocks_for(n), kThreads, 0, stream>>>(d_sorted_ids.get(), d_first.get(),
                                                                    static_cast<int>(n), d_representative.get());
      EXPANSE_CUDA(cudaGetLastError());
      timer.end();
      EXPANSE_CUDA(cudaStreamSynchronize(stream));
    } else {
      // No point repeats: the sorted points and their input indices are the sites already (the
      // compaction's copy took 0.27 ms at 4096^2 on the H100).
      d_site_points.swap(d_sorted);
      d_site_input.swap(d_sorted_ids);
    }
  }

  // The host's copy of what it prepared: the seam stage and the output need the sites, the
  // input indices and the representatives (grow_per_site only their number); the hull in site
  // ids. With a side stream, through its own pinned ring on another host thread while the stars
  // grow (without one: first, on the main stream). Copied straight into pageable memory on a
  // side stream instead, the copies held up the star kernel's launch (4096^2 uniform host to
  // host 230 -> 303 ms, H100).
  sites.scale_exponent = input.scan.scale_exponent;
  sites.integer_coordinates = input.scan.integer_coordinates;
  sites.bounds = bounds;
  resize_for_parallel_write(sites.points, m);
  resize_for_parallel_write(sites.input_index, m);
  Hull& hull = result.hull;
  hull.sites.resize(h);
  const bool alongside = ctx.side_stream != nullptr;
  double copies_ms = 0.0;
  const auto copy_to_host = [&, h, m, n](PinnedStaging& staging, cudaStream_t on) {
    const auto start = Clock::now();
    EXPANSE_CUDA(cudaSetDevice(ctx.device));
    staging.download(hull.sites.data(), d_hull_sites->get(), h * sizeof(int), on);
    staging.download(sites.points.data(), d_site_points.get(), m * sizeof(double2), on);
    staging.download(sites.input_index.data(), d_site_input.get(), m * sizeof(int), on);
    identity.get();
    if (m < n) staging.download(sites.representative.data(), d_representative.get(), n * sizeof(int), on);
    resize_for_parallel_write(hull.predecessor, m);
    parallel_chunks(m, [&](std::size_t, std::size_t begin, std::size_t end) {
      std::fill(hull.predecessor.begin() + static_cast<std::ptrdiff_t>(begin),
                hull.predecessor.begin() + static_cast<std::ptrdiff_t>(end), -1);
    });
    for (std::size_t k = 0; k < h; ++k) hull.predecessor[hull.sites[k]] = hull.sites[(k + h - 1) % h];
    copies_ms = ms_since(start);
  };
  std::future<void> copies;
  if (alongside)
    copies = std::async(std::launch::async, copy_to_host, std::ref(*ctx.side_staging), ctx.side_stream);
  else
    copy_to_host(*ctx.staging, stream);
  const auto host_prepared = Clock::now();

  std::vector<StageTime> prepare_stages = timer.collect();
  const SitesOnDevice on_device{d_site_points.get(), d_hull_sites->get(), long_runs};
  grow_per_site(ctx, GrowInput{sites, hull, input.layout, input.recycled}, result.grown, &on_device);
  const auto host_grown = Clock::now();
  if (copies.valid()) copies.get();
  auto& stages = result.grown.device_stages;
  stages.insert(stages.begin(), prepare_stages.begin(), prepare_stages.end());
  auto ms = [](auto a, auto b) { return std::chrono::duration<double, std::milli>(b - a).count(); };
  auto& host = result.grown.host_stages;
  host.insert(host.begin(), {{"cuda upload of the input (host)", ms(host_start, host_uploaded)},
                             {"cuda wait for the host's hull", hull_wait_ms},
                             {"cuda prepare on the device (host wait)", ms(host_uploaded, host_prepared) - hull_wait_ms}});
  host.push_back({alongside ? "cuda copy of the sites to the host (while the stars grow)"
                            : "cuda copy of the sites to the host (before the growth)",
                  copies_ms});
  if (alongside) host.push_back({"cuda wait for the sites' copy after the growth", ms(host_grown, Clock::now())});
  last_run_counters().short_morton_sort = short_sorted;
  last_run_counters().merge_hash_tables = hashed;
  last_run_counters().bytes_to_device = n * sizeof(double2) + h * sizeof(int);
  last_run_counters().bytes_to_host +=
      m * (sizeof(double2) + sizeof(int)) + h * sizeof(int) + (m < n ? n * sizeof(int) : 0);
  return true;
}

}  // namespace expanse::detail::cuda
