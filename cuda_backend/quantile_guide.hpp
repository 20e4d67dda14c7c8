#pragma once
// Where a quantile axis' cell lookup starts its binary search. Quantile cells put a column
// boundary at every (j / cells)-quantile of the sites' coordinates, so a coordinate's column is
// the number of boundaries at or below it: a binary search, ~12 dependent loads at 4096^2 points.
// A guide cuts the axis into bins and lists, for each bin, the boundaries that can bound a value
// in it, so the search runs over those few.
//
// The bins are not even steps of the coordinate: a heavy tail (kuzmin: its x and y are Cauchy
// distributed) stretches the sites' box some 10^7 times wider than the cluster that holds
// nearly every column, and even steps of that box put all of those columns in one or two bins.
// Here a bin is a step of the coordinate's distance from the axis' centre in its floating-point
// representation: its binary exponent and the top `p` bits of its mantissa. Every binade of
// distance gets the same 2^p bins, from the width of a central column out to the farthest site:
// near the centre a bin is a small step, in the tail a long one, as the columns are. Clusters
// away from the centre (the two gaussians, one each side of the median) are served better by
// even steps over the box, so an axis gets whichever of the two keys leaves the cheaper searches
// (quantile_guide_bin_cost: the columns each bin's values search, weighted by their share).
//
// Exact for any input: a bin is a monotone function of the coordinate (v - centre is correctly
// rounded, rounding is monotone, and so is the high word of a non-negative double), so
// bin(b) < bin(v) implies b < v and bin(b) > bin(v) implies b > v. The table counts, for each
// bin k, the boundaries whose bin is below k; the column of a value in bin k then lies between
// the counts of bins k and k + 1, with no margin for rounding needed. The host and CUDA evaluate
// the same operations, so a table built on one and read on the other still agrees. (Vulkan's
// quantile cells keep the full search: this guide in GLSL made its star shader slower, on
// lavapipe and on NVIDIA's driver, H100, 2026-11-25.)
#include <cstdint>
#include <cstring>
#include <vector>

#if defined(__CUDACC__)
#define EXPANSE_GUIDE_HD __host__ __device__
#else
#define EXPANSE_GUIDE_HD
#endif

namespace expanse::detail {

/// How an axis' values map to guide bins. Plain data: it travels in kernel parameters.
struct QuantileGuideKey {
  double centre = 0.0;           ///< logarithmic: the axis' centre; even: the first bin's start
  double scale = 0.0;            ///< even: bins per unit length
  std::uint32_t floor_word = 0;  ///< logarithmic: the smallest resolved distance's high word, shifted
  std::uint32_t shift = 20;      ///< logarithmic: 20 - p, the high-word bits below a bin
  int half = 1;                  ///< 2 * half bins (logarithmic: half each side of the centre)
  int logarithmic = 1;           ///< 0: even steps from `centre`
};

/// The high 32 bits of a double's representation (for non-negative doubles, monotone in value).
EXPANSE_GUIDE_HD inline std::uint32_t high_word(double m) {
#if defined(__CUDA_ARCH__)
  return static_cast<std::uint32_t>(__double2hiint(m));
#else
  std::uint64_t bits;
  std::memcpy(&bits, &m, sizeof bits);
  return static_cast<std::uint32_t>(bits >> 32);
#endif
}

/// The bin of v, in [0, 2 * key.half): the side of the centre by an exact comparison (so a
/// device that flushes a subnormal difference to zero still agrees), then the distance's step.
EXPANSE_GUIDE_HD inline int quantile_guide_bin(const QuantileGuideKey& key, double v) {
  if (!key.logarithmic) {  // (v - centre) * scale, rounded twice: monotone too
    const double t = (v - key.centre) * key.scale;
    return t >= 0.0 ? (t < 2.0 * key.half ? static_cast<int>(t) : 2 * key.half - 1) : 0;
  }
  const bool below = v < key.centre;
  const double d = below ? key.centre - v : v - key.centre;
  const std::uint32_t word = high_word(d) >> key.shift;
  const std::uint32_t step = word > key.floor_word ? word - key.floor_word : 0u;
  const int s = step < static_cast<std::uint32_t>(key.half) ? static_cast<int>(step) : key.half - 1;
  return below ? key.half - 1 - s : key.half + s;
}

/// Entry k (0 .. 2 * key.half) of an axis' table: how many of the `count` ascending boundaries
/// bounds[0 .. count) lie in bins below k. The bins of ascending boundaries ascend, so a binary
/// search counts them.
EXPANSE_GUIDE_HD inline int quantile_guide_entry(const double* bounds, int count, const QuantileGuideKey& key, int k) {
  int lo = 0, hi = count;
  while (lo < hi) {
    const int mid = (lo + hi) >> 1;
    if (quantile_guide_bin(key, bounds[mid]) < k)
      lo = mid + 1;
    else
      hi = mid;
  }
  return lo;
}

/// What searching with a table costs: over its bins, the columns between the bin's entries
/// (a value's column lies among them) times the binary search's steps over them. Columns hold
/// equal shares of the sites, so this weighs each bin by how often it is looked up. Exact in
/// integers: the host and a device's parallel sum agree.
EXPANSE_GUIDE_HD inline long long quantile_guide_columns_cost(int columns) {
  int steps = 0;
  while ((1 << steps) < columns + 1) ++steps;
  return static_cast<long long>(columns) * steps;
}
EXPANSE_GUIDE_HD inline long long quantile_guide_bin_cost(const int* first, int k) {
  return quantile_guide_columns_cost(first[k + 1] - first[k]);
}

/// The most table entries an axis of `cells` columns can need (either key's bound).
inline int quantile_guide_capacity(int cells) {
  const int half = (cells > 1100 ? 2 * cells : 2200) + 1;
  return 2 * half + 1;
}

/// An axis' even key: 2 * cells bins over [lo, hi].
EXPANSE_GUIDE_HD inline QuantileGuideKey plan_even_quantile_guide(double lo, double hi, int cells) {
  QuantileGuideKey key;
  key.logarithmic = 0;
  key.centre = lo;
  key.half = cells;
  key.scale = 2.0 * cells / (hi - lo);  // inf for a flat axis: every value in the first or last bin
  return key;
}

/// An axis' logarithmic key for its cells - 1 ascending boundaries bounds[0 ..): centred on
/// the median boundary, resolving distances from an eighth of a central column out to the
/// farthest of [lo, hi], with about 2 * cells bins on each side. Needs cells >= 4.
EXPANSE_GUIDE_HD inline QuantileGuideKey plan_logarithmic_quantile_guide(const double* bounds, int cells, double lo,
                                                                          double hi) {
  QuantileGuideKey key;
  const double centre = bounds[cells / 2 - 1];
  key.centre = centre;
  const double reach = (hi - centre > centre - lo ? hi - centre : centre - lo);
  constexpr double smallest_normal = 2.2250738585072014e-308;
  double resolved = (bounds[cells / 2] - bounds[cells / 2 - 2]) / 16.0;
  if (!(resolved >= smallest_normal)) resolved = reach * 0x1p-40;  // duplicates at the centre
  if (!(resolved >= smallest_normal)) resolved = smallest_normal;
  const double farthest = reach > resolved ? reach : resolved;
  // Binades from `resolved` to `farthest`, then 2^p bins each, p as large as 2 * cells bins a
  // side allow.
  const int binades = static_cast<int>((high_word(farthest) >> 20) - (high_word(resolved) >> 20)) + 1;
  int p = 0;
  while (p < 20 && (binades << (p + 1)) <= 2 * cells) ++p;
  key.shift = static_cast<std::uint32_t>(20 - p);
  key.floor_word = high_word(resolved) >> key.shift;
  key.half = static_cast<int>((high_word(farthest) >> key.shift) - key.floor_word) + 1;
  return key;
}

/// Fills `table` (2 * key.half + 1 entries) for the cells - 1 ascending boundaries bounds[0 ..)
/// and returns its cost (quantile_guide_bin_cost summed).
inline long long fill_quantile_guide(const double* bounds, int cells, const QuantileGuideKey& key,
                                     std::vector<int>& table) {
  table.resize(2 * key.half + 1);
  for (int k = 0; k <= 2 * key.half; ++k) table[k] = quantile_guide_entry(bounds, cells - 1, key, k);
  long long cost = 0;
  for (int k = 0; k < 2 * key.half; ++k) cost += quantile_guide_bin_cost(table.data(), k);
  return cost;
}

/// The guide of an axis of `cells` columns (cells - 1 ascending boundaries bounds[0 ..) over
/// [lo, hi]): the cheaper key of the two, its table in `table`. As the CUDA backend's
/// guide_kernel chooses on the device.
inline QuantileGuideKey build_quantile_guide(const double* bounds, int cells, double lo, double hi,
                                             std::vector<int>& table) {
  const QuantileGuideKey logarithmic = plan_logarithmic_quantile_guide(bounds, cells, lo, hi);
  const QuantileGuideKey even = plan_even_quantile_guide(lo, hi, cells);
  std::vector<int> other;
  const long long log_cost = fill_quantile_guide(bounds, cells, logarithmic, table);
  const long long even_cost = fill_quantile_guide(bounds, cells, even, other);
  if (even_cost < log_cost) {
    table.swap(other);
    return even;
  }
  return logarithmic;
}

}  // namespace expanse::detail
