#include "input/morton.hpp"

#include "input/parallel.hpp"

#include <algorithm>
#include <numeric>

namespace expanse::detail {

Quantiser::Quantiser(const Box& box) : origin_x(box.min_x), origin_y(box.min_y) {
  const double side = std::max(box.max_x - box.min_x, box.max_y - box.min_y);
  scale = side > 0 ? static_cast<double>(max) / side : 1.0;
}

SplitPlan::SplitPlan(const std::vector<std::uint64_t>& sample, std::size_t target) {
  const std::size_t cap = std::max<std::size_t>(1, sample.size() / std::max<std::size_t>(1, target));
  struct Leaf {
    std::size_t slot, count;
  };
  std::vector<Leaf> leaves;  // table entries that name a bucket, in code order
  table_.assign(std::size_t{1} << first_bits, 0);
  // Fills the table at `offset` (2^bits entries for the digit at `shift`) from `codes`, the
  // sample codes under it; a digit with more than `cap` of them gets a table of its own.
  const auto fill = [&](const auto& self, std::vector<std::uint64_t> codes, std::size_t offset, int bits,
                        int shift) -> void {
    const std::size_t size = std::size_t{1} << bits;
    std::vector<std::size_t> start(size + 1, 0);
    for (std::uint64_t code : codes) ++start[((code >> shift) & (size - 1)) + 1];
    for (std::size_t d = 0; d < size; ++d) start[d + 1] += start[d];
    std::vector<std::uint64_t> grouped(codes.size());
    {
      std::vector<std::size_t> next(start.begin(), start.end() - 1);
      for (std::uint64_t code : codes) grouped[next[(code >> shift) & (size - 1)]++] = code;
    }
    codes.clear();
    codes.shrink_to_fit();
    for (std::size_t d = 0; d < size; ++d) {
      const std::size_t count = start[d + 1] - start[d];
      if (count > cap && shift > 0) {
        const std::size_t table = table_.size();
        table_.resize(table + (std::size_t{1} << next_bits), 0);
        table_[offset + d] = refined | static_cast<std::uint32_t>(table);
        self(self, std::vector<std::uint64_t>(grouped.begin() + static_cast<std::ptrdiff_t>(start[d]),
                                              grouped.begin() + static_cast<std::ptrdiff_t>(start[d + 1])),
             table, next_bits, shift - next_bits);
      } else {
        leaves.push_back({offset + d, count});
      }
    }
  };
  fill(fill, sample, 0, first_bits, first_shift);
  // Consecutive entries share a bucket while their sample counts add up to at most cap.
  std::uint32_t bucket = 0;
  std::size_t held = 0;
  for (const Leaf& leaf : leaves) {
    if (held > 0 && held + leaf.count > cap) {
      ++bucket;
      held = 0;
    }
    table_[leaf.slot] = bucket;
    held += leaf.count;
  }
  buckets_ = std::size_t{bucket} + 1;
}

namespace {

// The sort works on two pairs of arrays: side 0 is the caller's (where the result must end),
// side 1 scratch of the same size. A range of elements lives on one side at a time.
struct Sides {
  std::uint64_t* codes[2];
  std::int32_t* values[2];
};

// Elements [begin, end) on side `side`, equal in every code bit at or above `shift`.
struct Range {
  std::size_t begin, end;
  int side;
  int shift;
};

void move_to_side0(const Sides& s, const Range& r) {
  if (r.side == 0) return;
  std::copy(s.codes[1] + r.begin, s.codes[1] + r.end, s.codes[0] + r.begin);
  std::copy(s.values[1] + r.begin, s.values[1] + r.end, s.values[0] + r.begin);
}

// Sorts a range on one thread: insertion sort when it is short, else distribution on the next
// digit (about one bucket per element) and recursion. Stable throughout.
void sort_small(const Sides& s, const Range& r) {
  const std::size_t m = r.end - r.begin;
  if (m <= 1 || r.shift == 0) {
    move_to_side0(s, r);
    return;
  }
  if (m <= 32) {
    std::uint64_t* codes = s.codes[r.side] + r.begin;
    std::int32_t* values = s.values[r.side] + r.begin;
    for (std::size_t i = 1; i < m; ++i) {
      const std::uint64_t code = codes[i];
      const std::int32_t value = values[i];
      std::size_t j = i;
      for (; j > 0 && codes[j - 1] > code; --j) {
        codes[j] = codes[j - 1];
        values[j] = values[j - 1];
      }
      codes[j] = code;
      values[j] = value;
    }
    move_to_side0(s, r);
    return;
  }
  int bits = 1;
  while (bits < 11 && (std::size_t{2} << bits) <= m) ++bits;
  bits = std::min(bits, r.shift);
  const int shift = r.shift - bits;
  const std::size_t radix = std::size_t{1} << bits;
  const std::uint64_t* codes = s.codes[r.side];
  const std::int32_t* values = s.values[r.side];
  std::vector<std::uint32_t> start(radix + 1, 0);
  for (std::size_t i = r.begin; i < r.end; ++i) ++start[((codes[i] >> shift) & (radix - 1)) + 1];
  if (std::find(start.begin() + 1, start.end(), m) != start.end()) {  // one digit: nothing moves
    sort_small(s, {r.begin, r.end, r.side, shift});
    return;
  }
  for (std::size_t d = 0; d < radix; ++d) start[d + 1] += start[d];
  std::vector<std::uint32_t> next(start.begin(), start.end() - 1);
  const int other = 1 - r.side;
  std::uint64_t* out_codes = s.codes[other] + r.begin;
  std::int32_t* out_values = s.values[other] + r.begin;
  for (std::size_t i = r.begin; i < r.end; ++i) {
    const std::uint32_t slot = next[(codes[i] >> shift) & (radix - 1)]++;
    out_codes[slot] = codes[i];
    out_values[slot] = values[i];
  }
  for (std::size_t d = 0; d < radix; ++d) {
    sort_small(s, {r.begin + start[d], r.begin + start[d + 1], other, shift});
  }
}

// Distributes a large range on its next 12 bits with all threads (each chunk counts, then
// scatters stably), recursing into buckets that are still large; collects the rest as tasks.
void sort_large(const Sides& s, const Range& r, std::size_t large, std::vector<Range>& tasks) {
  const std::size_t m = r.end - r.begin;
  if (m <= large || r.shift == 0) {
    tasks.push_back(r);
    return;
  }
  const int bits = std::min(12, r.shift);
  const int shift = r.shift - bits;
  const std::size_t radix = std::size_t{1} << bits;
  const std::size_t chunks = chunk_count(m);
  const std::uint64_t* codes = s.codes[r.side];
  const std::int32_t* values = s.values[r.side];
  std::vector<std::uint32_t> count(chunks * radix, 0);
  parallel_chunks(m, chunks, [&](std::size_t c, std::size_t begin, std::size_t end) {
    std::uint32_t* mine = count.data() + c * radix;
    for (std::size_t i = r.begin + begin; i < r.begin + end; ++i) ++mine[(codes[i] >> shift) & (radix - 1)];
  });
  const std::vector<std::size_t> bucket_start = distribution_slots(count, chunks, radix);
  for (std::size_t d = 0; d < radix; ++d) {
    if (bucket_start[d + 1] - bucket_start[d] == m) {  // one digit: nothing moves
      sort_large(s, {r.begin, r.end, r.side, shift}, large, tasks);
      return;
    }
  }
  const int other = 1 - r.side;
  std::uint64_t* out_codes = s.codes[other] + r.begin;
  std::int32_t* out_values = s.values[other] + r.begin;
  parallel_chunks(m, chunks, [&](std::size_t c, std::size_t begin, std::size_t end) {
    std::uint32_t* next = count.data() + c * radix;
    for (std::size_t i = r.begin + begin; i < r.begin + end; ++i) {
      const std::uint32_t slot = next[(codes[i] >> shift) & (radix - 1)]++;
      out_codes[slot] = codes[i];
      out_values[slot] = values[i];
    }
  });
  for (std::size_t d = 0; d < radix; ++d) {
    sort_large(s, {r.begin + bucket_start[d], r.begin + bucket_start[d + 1], other, shift}, large, tasks);
  }
}

}  // namespace

void sort_by_code_sequential(std::uint64_t* codes, std::int32_t* values, std::uint64_t* scratch_codes,
                             std::int32_t* scratch_values, std::size_t m, int shift) {
  sort_small({{codes, scratch_codes}, {values, scratch_values}}, {0, m, 0, shift});
}

void sort_by_code(HostVector<std::uint64_t>& codes, HostVector<std::int32_t>& values) {
  const std::size_t n = codes.size();
  if (n < 2) return;
  // Slot counters are 32-bit: n < 2^31 (prepare_sites refuses more).
  HostVector<std::uint64_t> codes_tmp;
  HostVector<std::int32_t> values_tmp;
  resize_for_parallel_write(codes_tmp, n);
  resize_for_parallel_write(values_tmp, n);
  const Sides sides{{codes.data(), codes_tmp.data()}, {values.data(), values_tmp.data()}};
  // Ranges above `large` are split with all threads; the rest are sorted one per thread.
  const std::size_t large = std::max<std::size_t>(std::size_t{1} << 16, n / (8 * host_threads()));
  std::vector<Range> tasks;
  sort_large(sides, {0, n, 0, 2 * Quantiser::bits}, large, tasks);
  parallel_tasks(tasks.size(), [&](std::size_t t) { sort_small(sides, tasks[t]); });
}

}  // namespace expanse::detail
