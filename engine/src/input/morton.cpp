#include "input/morton.hpp"

#include "input/parallel.hpp"

#include <algorithm>
#include <numeric>
#include <utility>

namespace expanse::detail {

Quantiser::Quantiser(const Box& box) : origin_x(box.min_x), origin_y(box.min_y) {
  const double side = std::max(box.max_x - box.min_x, box.max_y - box.min_y);
  scale = side > 0 ? static_cast<double>(max) / side : 1.0;
}

std::uint64_t morton_code(std::uint32_t qx, std::uint32_t qy) {
  const auto spread = [](std::uint32_t v) {
    std::uint64_t x = v;
    x = (x | (x << 16)) & 0x0000FFFF0000FFFFull;
    x = (x | (x << 8)) & 0x00FF00FF00FF00FFull;
    x = (x | (x << 4)) & 0x0F0F0F0F0F0F0F0Full;
    x = (x | (x << 2)) & 0x3333333333333333ull;
    x = (x | (x << 1)) & 0x5555555555555555ull;
    return x;
  };
  return spread(qx) | (spread(qy) << 1);
}

void sort_by_code(std::vector<std::uint64_t>& codes, std::vector<std::int32_t>& values) {
  if (std::is_sorted(codes.begin(), codes.end())) return;
  // LSD radix sort, stable. Each chunk counts its own digits; the scatter offsets of chunk c for
  // digit d come after every earlier digit and after chunks < c of digit d, so the result is
  // the same as a sequential pass.
  constexpr int digit_bits = 15;  // 60-bit codes in four passes; 32K counters stay in L2
  constexpr std::size_t radix = std::size_t{1} << digit_bits;
  const std::size_t n = codes.size();
  const std::size_t chunks = chunk_count(n);
  std::vector<std::uint64_t> codes_tmp(n);
  std::vector<std::int32_t> values_tmp(n);
  std::vector<std::vector<std::size_t>> count(chunks, std::vector<std::size_t>(radix));
  for (int shift = 0; shift < 2 * Quantiser::bits; shift += digit_bits) {
    parallel_chunks(n, [&](std::size_t c, std::size_t begin, std::size_t end) {
      auto& mine = count[c];
      std::fill(mine.begin(), mine.end(), 0);
      for (std::size_t i = begin; i < end; ++i) ++mine[(codes[i] >> shift) & (radix - 1)];
    });
    std::size_t sum = 0;
    for (std::size_t d = 0; d < radix; ++d) {
      for (std::size_t c = 0; c < chunks; ++c) sum += std::exchange(count[c][d], sum);
    }
    parallel_chunks(n, [&](std::size_t c, std::size_t begin, std::size_t end) {
      auto& next = count[c];
      for (std::size_t i = begin; i < end; ++i) {
        const std::size_t slot = next[(codes[i] >> shift) & (radix - 1)]++;
        codes_tmp[slot] = codes[i];
        values_tmp[slot] = values[i];
      }
    });
    codes.swap(codes_tmp);
    values.swap(values_tmp);
  }
}

}  // namespace expanse::detail
