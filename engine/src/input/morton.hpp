#pragma once
// Quantisation and Morton (Z-order) codes shared by the bucket tree and the spatial sort.
// Quantisation is monotone in the real coordinates, which is what makes integer box tests safe.
#include <cstdint>
#include <vector>

#include "input/parallel.hpp"
#include "input/site_set.hpp"

// The quantisation and the codes also run on CUDA devices (prepare_on_device.cu sorts the raw
// input by them), which must compute the same codes: the device build does not contract either.
#if defined(__CUDACC__)
#define EXPANSE_MORTON_HD __host__ __device__
#else
#define EXPANSE_MORTON_HD
#endif

namespace expanse::detail {

struct Quantiser {
  static constexpr int bits = 30;
  static constexpr std::uint32_t max = (1u << bits) - 1;

  double origin_x = 0, origin_y = 0, scale = 1;

  /// A square domain over `box`, so squares in quanta are squares in the plane.
  explicit Quantiser(const Box& box);
  EXPANSE_MORTON_HD std::uint32_t x(double v) const { return clamp((v - origin_x) * scale); }
  EXPANSE_MORTON_HD std::uint32_t y(double v) const { return clamp((v - origin_y) * scale); }

 private:
  EXPANSE_MORTON_HD static std::uint32_t clamp(double q) {
    if (!(q > 0.0)) return 0;
    if (q >= static_cast<double>(max)) return max;
    return static_cast<std::uint32_t>(q);
  }
};

/// v's bits spread to the even bits of the result.
EXPANSE_MORTON_HD inline std::uint64_t spread_bits(std::uint32_t v) {
  std::uint64_t x = v;
  x = (x | (x << 16)) & 0x0000FFFF0000FFFFull;
  x = (x | (x << 8)) & 0x00FF00FF00FF00FFull;
  x = (x | (x << 4)) & 0x0F0F0F0F0F0F0F0Full;
  x = (x | (x << 2)) & 0x3333333333333333ull;
  x = (x | (x << 1)) & 0x5555555555555555ull;
  return x;
}

/// Interleaves x (even bits) and y (odd bits).
EXPANSE_MORTON_HD inline std::uint64_t morton_code(std::uint32_t qx, std::uint32_t qy) {
  return spread_bits(qx) | (spread_bits(qy) << 1);
}

/// The top-level split of a Morton sort, planned from a sample of the codes: buckets that are
/// consecutive intervals of codes, each holding about 1/target of the sample (more where one
/// code alone holds more). bucket(code) never decreases as code grows, and is below buckets().
/// A table of the top 12 code bits refines a digit that holds too much of the sample by
/// tables of the next 8 bits, down to single codes: a site of a dense cluster looks up a
/// few entries, one of an even spread one.
class SplitPlan {
 public:
  SplitPlan(const std::vector<std::uint64_t>& sample, std::size_t target);
  std::size_t buckets() const { return buckets_; }
  /// True when some code takes more than one table to look up.
  bool deep() const { return table_.size() > (std::size_t{1} << first_bits); }
  std::uint32_t bucket(std::uint64_t code) const {
    std::uint32_t entry = table_[code >> first_shift];
    int shift = first_shift;
    while (entry & refined) {
      shift -= next_bits;
      entry = table_[(entry & ~refined) + ((code >> shift) & ((1u << next_bits) - 1))];
    }
    return entry;
  }

 private:
  static constexpr int first_bits = 12, next_bits = 8;
  static constexpr int first_shift = 2 * Quantiser::bits - first_bits;
  static_assert(first_shift % next_bits == 0, "the last table must end at bit 0");
  static constexpr std::uint32_t refined = 1u << 31;  // entry: offset of the next table
  std::vector<std::uint32_t> table_;
  std::size_t buckets_ = 1;
};

/// Sorts (codes, values) by code, stably: equal codes keep their order. codes must be
/// 2 * Quantiser::bits wide. Radix sort, most significant digits first, on all host threads.
void sort_by_code(HostVector<std::uint64_t>& codes, HostVector<std::int32_t>& values);

/// sort_by_code on the calling thread for m elements whose codes all agree in the bits at and
/// above `shift`; scratch_codes and scratch_values hold m elements each.
void sort_by_code_sequential(std::uint64_t* codes, std::int32_t* values, std::uint64_t* scratch_codes,
                             std::int32_t* scratch_values, std::size_t m, int shift);


}  // namespace expanse::detail
