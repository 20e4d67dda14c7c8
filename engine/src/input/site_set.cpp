#include "input/site_set.hpp"

#include <cfloat>
#include <cmath>
#include <algorithm>
#include <atomic>
#include <bit>
#include <limits>
#include <ranges>
#include <string>

#include "expanse/error.hpp"
#include "input/morton.hpp"
#include "input/parallel.hpp"

namespace expanse::detail {
namespace {

[[noreturn]] void throw_non_finite(std::size_t index, const Point2& p) {
  throw Error(ErrorCode::invalid_input,
              "point " + std::to_string(index) + " has a non-finite coordinate (" +
                  std::to_string(p.x) + ", " + std::to_string(p.y) + ")");
}

// The largest power-of-two exponent e such that multiplying every coordinate by 2^e is exact
// (no nonzero value may fall below the smallest normal double) and brings the largest
// magnitude into [0.5, 1). Exact scaling keeps predicates unchanged and keeps degree-4 terms
// far from under- and overflow for all but extremely spread inputs (which the predicates then
// hand to their GMP path).
int exact_scale_exponent(double max_abs, double min_nonzero_abs) {
  if (max_abs == 0.0) return 0;
  int max_exp = 0;
  std::frexp(max_abs, &max_exp);  // max_abs = m * 2^max_exp, m in [0.5, 1)
  int e = -max_exp;
  if (e < 0) {
    int min_exp = 0;
    std::frexp(min_nonzero_abs, &min_exp);
    // min_nonzero_abs * 2^e must stay >= DBL_MIN = 2^-1022, i.e. min_exp - 1 + e >= -1022.
    const int limit = -1022 - (min_exp - 1);
    if (e < limit) e = limit;
  }
  return e;
}

// x's bits as an unsigned number in the order of x (for x not NaN; -0.0 before +0.0).
std::uint64_t ordered_bits(double x) {
  const auto bits = std::bit_cast<std::uint64_t>(x);
  return (bits >> 63) ? ~bits : bits | (std::uint64_t{1} << 63);
}

}  // namespace

InputScan scan_input(std::span<const Point2> input) {
  if (input.size() > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max())) {
    throw Error(ErrorCode::too_large, "at most 2^31 - 1 points are supported, got " +
                                          std::to_string(input.size()));
  }
  const std::size_t n = input.size();
  const std::size_t chunks = chunk_count(n);

  // Validation, the magnitude range and the bounding box, per chunk; chunk order makes the
  // first bad point the one reported. The box is taken before scaling: scaling by 2^e is exact
  // and monotone, so it commutes with min and max (ties keep the first point either way).
  struct Scan {
    double max_abs = 0.0;
    double min_nonzero_abs = std::numeric_limits<double>::infinity();
    Box box{};
    bool integers = true;
  };
  std::vector<Scan> scans(std::max<std::size_t>(chunks, 1));
  parallel_chunks(n, chunks, [&](std::size_t chunk, std::size_t begin, std::size_t end) {
    Scan r;
    for (std::size_t i = begin; i < end; ++i) {
      const Point2& p = input[i];
      if (!std::isfinite(p.x) || !std::isfinite(p.y)) throw_non_finite(i, p);
      for (double v : {std::fabs(p.x), std::fabs(p.y)}) {
        if (v > r.max_abs) r.max_abs = v;
        if (v != 0.0 && v < r.min_nonzero_abs) r.min_nonzero_abs = v;
      }
      r.integers &= (std::trunc(p.x) == p.x) & (std::trunc(p.y) == p.y);
      if (i == begin) r.box = {p.x, p.y, p.x, p.y};
      r.box.min_x = std::min(r.box.min_x, p.x);
      r.box.max_x = std::max(r.box.max_x, p.x);
      r.box.min_y = std::min(r.box.min_y, p.y);
      r.box.max_y = std::max(r.box.max_y, p.y);
    }
    scans[chunk] = r;
  });
  double max_abs = 0.0;
  double min_nonzero_abs = std::numeric_limits<double>::infinity();
  Box box = scans[0].box;
  bool integers = true;
  for (const Scan& r : scans) {
    integers = integers && r.integers;
    max_abs = std::max(max_abs, r.max_abs);
    min_nonzero_abs = std::min(min_nonzero_abs, r.min_nonzero_abs);
    box.min_x = std::min(box.min_x, r.box.min_x);
    box.max_x = std::max(box.max_x, r.box.max_x);
    box.min_y = std::min(box.min_y, r.box.min_y);
    box.max_y = std::max(box.max_y, r.box.max_y);
  }

  InputScan scan;
  scan.integer_coordinates = integers;
  scan.scale_exponent = exact_scale_exponent(max_abs, min_nonzero_abs);
  scan.factor = scan.scale_exponent <= 1023 ? std::ldexp(1.0, scan.scale_exponent) : 0.0;
  if (std::isfinite(min_nonzero_abs)) scan.smallest_nonzero = std::ldexp(min_nonzero_abs, scan.scale_exponent);
  if (n > 0) {
    const Point2 low = scan.scaled({box.min_x, box.min_y}), high = scan.scaled({box.max_x, box.max_y});
    scan.bounds = {low.x, low.y, high.x, high.y};
  }
  return scan;
}

namespace {

bool point_less(const Point2& a, const Point2& b) { return a.x < b.x || (a.x == b.x && a.y < b.y); }

// prepare_sites, step by step. Morton order, stable: equal points share a code, so each group
// of duplicates ends up in one run of equal codes, its smallest input index first. The scaled
// points travel with the sort (no random gather afterwards): one pass distributes them into
// buckets (intervals of codes) straight into sites.points and sites.input_index, stably; then
// each bucket is sorted where it lies, and duplicates are merged.
class SitePreparation {
 public:
  SitePreparation(std::span<const Point2> input, const InputScan& scan)
      : input_(input), scan_(scan), n_(input.size()), chunks_(chunk_count(n_)), quantiser_(scan.bounds),
        plan_(plan_split()) {
    sites_.scale_exponent = scan.scale_exponent;
    sites_.bounds = scan.bounds;
    sites_.integer_coordinates = scan.integer_coordinates;
  }

  SiteSet run() {
    distribute();
    sort_buckets();
    if (repeated_.load() > 0) merge_duplicates();  // else every point is distinct (the usual case)
    return std::move(sites_);
  }

 private:
  Point2 scaled(const Point2& p) const { return scan_.scaled(p); }
  std::uint64_t code_of(const Point2& p) const { return morton_code(quantiser_.x(p.x), quantiser_.y(p.y)); }
  bool repeats_previous(std::size_t k) const {
    const auto& sorted = sites_.points;
    return k > 0 && sorted[k - 1].x == sorted[k].x && sorted[k - 1].y == sorted[k].y;
  }

  // The top-level split: buckets that are intervals of codes, each meant to hold about 2^16
  // sites (few enough buckets that the distribution writes each one's next cache line before it
  // is evicted). Taking the top bits of the code does that for uniform input only: clustered or
  // heavy-tailed input put most sites in a few top-bit buckets (kuzmin at 4M: four buckets of
  // ~1M), which then took many full passes on all threads, each with fresh buffers. So the split
  // follows a strided sample of the codes instead (SplitPlan).
  SplitPlan plan_split() const {
    std::size_t target = 2;
    while (target < 1024 && (n_ >> 16) >= target) target *= 2;
    const std::size_t samples = std::min<std::size_t>(n_, std::size_t{1} << 15);
    std::vector<std::uint64_t> sample(samples);
    // One site from each of `samples` equal stretches of the input, at a scrambled place in
    // its stretch: a fixed stride aliases with periodic input (the gaussian set alternates its
    // two clusters: at 4096^2 every strided sample came from one, and the other's 8.3M sites
    // fell into one bucket).
    parallel_chunks(samples, chunk_count(samples, 4096), [&](std::size_t, std::size_t begin, std::size_t end) {
      for (std::size_t k = begin; k < end; ++k) {
        const std::size_t first = k * n_ / samples, last = (k + 1) * n_ / samples;
        std::uint64_t z = (k + 1) * 0x9e3779b97f4a7c15ull;  // splitmix64's finaliser
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
        z ^= z >> 31;
        sample[k] = code_of(scaled(input_[first + z % (last - first)]));
      }
    });
    return SplitPlan(sample, target);
  }

  // Counts each chunk's sites per bucket, then scatters them, stably, into sites.points and
  // sites.input_index; bucket_start_ then says where each bucket begins.
  void distribute() {
    const std::size_t n = n_, chunks = chunks_, buckets = plan_.buckets();
    std::vector<std::uint32_t> next(chunks * buckets, 0);
    // Where the plan is deep (a site of a dense cluster looks up several tables), each site's
    // bucket is kept from the count for the distribution (kuzmin 4M: 131 -> 116 ms, 140 -> 137);
    // else it is found again (uniform 4M: keeping it cost 76 -> 81 ms).
    const bool keep = plan_.deep() && buckets <= 65536;
    HostVector<std::uint16_t> bucket_of;
    if (keep) resize_for_parallel_write(bucket_of, n);
    parallel_chunks(n, chunks, [&](std::size_t chunk, std::size_t begin, std::size_t end) {
      std::uint32_t* mine = next.data() + chunk * buckets;
      if (!keep) {
        for (std::size_t i = begin; i < end; ++i) ++mine[plan_.bucket(code_of(scaled(input_[i])))];
        return;
      }
      for (std::size_t i = begin; i < end; ++i) {
        const std::uint32_t bucket = plan_.bucket(code_of(scaled(input_[i])));
        bucket_of[i] = static_cast<std::uint16_t>(bucket);
        ++mine[bucket];
      }
    });
    bucket_start_ = distribution_slots(next, chunks, buckets);
    resize_for_parallel_write(sites_.points, n);  // scattered first writes, on all threads
    resize_for_parallel_write(sites_.input_index, n);
    parallel_chunks(n, chunks, [&](std::size_t chunk, std::size_t begin, std::size_t end) {
      std::uint32_t* mine = next.data() + chunk * buckets;
      const auto scatter = [&](auto bucket) {
        for (std::size_t i = begin; i < end; ++i) {
          const Point2 p = scaled(input_[i]);
          const std::uint32_t slot = mine[bucket(i, p)]++;
          sites_.points[slot] = p;
          sites_.input_index[slot] = static_cast<std::int32_t>(i);
        }
      };
      if (keep) {
        scatter([&](std::size_t i, const Point2&) { return bucket_of[i]; });
      } else {
        scatter([&](std::size_t, const Point2& p) { return plan_.bucket(code_of(p)); });
      }
    });
  }

  // Buckets in input order within; sorting (code, position in the bucket) and permuting sorts
  // by (code, input index).
  //
  // Runs of equal codes (points closer than one quantum of the box: clusters far smaller than
  // the box, as in heavy-tailed inputs, and duplicates) are put in (x, y) order, stably, so
  // that equal points stand side by side, their smallest input index first. Looking for an
  // equal point through a run in input order cost its length squared (2M kuzmin sites on the
  // 2-core VM: 727 ms against 235 after, both under the same load; 4096^2 on the H100's host:
  // 1,486 against 383 ms), and more still for many distinct points crowded into one run. A run
  // has one code, so it lies in one bucket: a bucket sorted on one thread orders its runs and
  // counts its repeated points while it is in cache.
  void sort_buckets() {
    const std::size_t large = std::max<std::size_t>(std::size_t{1} << 16, n_ / (4 * host_threads()));
    std::vector<std::size_t> small, big;
    for (std::size_t d = 0; d < plan_.buckets(); ++d) {
      const std::size_t m = bucket_start_[d + 1] - bucket_start_[d];
      if (m > large) big.push_back(d);
      else if (m > 1) small.push_back(d);
    }
    // Task 0 writes the representatives as if every point were distinct (the usual case; the
    // merge rewrites them all otherwise). They are a std::vector (Mesh::representative):
    // written whole on one thread, once, while the other threads sort, instead of a zeroing pass
    // on one thread and an identity pass on all after the sort.
    parallel_tasks(small.size() + 1, [&](std::size_t task) {
      if (task == 0) {
        write_identity_representatives();
      } else {
        sort_small_bucket(small[task - 1]);
      }
    });
    for (const std::size_t d : big) sort_big_bucket(d);  // skewed inputs: too large for one thread
  }

  void write_identity_representatives() {
    auto& representative = sites_.representative;
    representative.reserve(n_);
    advise_huge_pages(representative.data(), n_ * sizeof(std::int32_t));
    const auto ids = std::views::iota(std::int32_t{0}, static_cast<std::int32_t>(n_));
    representative.assign(ids.begin(), ids.end());
  }

  // One bucket on one thread: sorted by code, its runs of equal codes by point.
  void sort_small_bucket(std::size_t d) {
    const std::size_t lo = bucket_start_[d], m = bucket_start_[d + 1] - lo;
    thread_local std::vector<std::uint64_t> codes, codes_scratch;
    thread_local std::vector<std::int32_t> position, position_scratch, index;
    thread_local std::vector<Point2> points;
    for (auto* v : {&codes, &codes_scratch}) v->resize(std::max(v->size(), m));
    for (auto* v : {&position, &position_scratch, &index}) v->resize(std::max(v->size(), m));
    points.resize(std::max(points.size(), m));
    std::uint64_t differ = 0;  // the bits in which the bucket's codes differ
    for (std::size_t j = 0; j < m; ++j) {
      points[j] = sites_.points[lo + j];
      index[j] = sites_.input_index[lo + j];
      codes[j] = code_of(points[j]);
      differ |= codes[j] ^ codes[0];
      position[j] = static_cast<std::int32_t>(j);
    }
    sort_by_code_sequential(codes.data(), position.data(), codes_scratch.data(), position_scratch.data(), m,
                            std::bit_width(differ));
    std::size_t repeats_here = 0;
    for (std::size_t k = 0; k < m;) {
      std::size_t last = k + 1;
      while (last < m && codes[last] == codes[k]) ++last;
      if (last - k >= 2) {  // positions in the run are in input order: ties keep it
        std::int32_t* run = position.data() + k;
        sort_run_by_point(points.data(), run, last - k, codes_scratch.data(), position_scratch.data());
        for (std::size_t j = k + 1; j < last; ++j) {
          const Point2 &before = points[position[j - 1]], &here = points[position[j]];
          repeats_here += before.x == here.x && before.y == here.y;
        }
      }
      k = last;
    }
    if (repeats_here > 0) repeated_.fetch_add(repeats_here, std::memory_order_relaxed);
    for (std::size_t k = 0; k < m; ++k) {
      sites_.points[lo + k] = points[position[k]];
      sites_.input_index[lo + k] = index[position[k]];
    }
  }

  // The positions run[0, length) of one run of equal codes, in input order, put in (x, y) order
  // (ties: position) in place; keys and values are scratch of `length` entries.
  static void sort_run_by_point(const Point2* points, std::int32_t* run, std::size_t length, std::uint64_t* keys,
                                std::int32_t* values) {
    const auto by_point = [&](std::int32_t a, std::int32_t b) {
      return point_less(points[a], points[b]) || (!point_less(points[b], points[a]) && a < b);
    };
    if (length <= 32) {
      std::sort(run, run + length, by_point);
      return;
    }
    // A long run (kuzmin's centre: 3.85M of 4M sites in runs, up to 13K long): sorted stably
    // by x as a radix key (its bits in an order that follows x, -0.0 as +0.0 so that equal x
    // means equal key), then equal x by (y, position).
    thread_local std::vector<std::uint64_t> run_keys_scratch;
    thread_local std::vector<std::int32_t> run_values_scratch;
    run_keys_scratch.resize(std::max(run_keys_scratch.size(), length));
    run_values_scratch.resize(std::max(run_values_scratch.size(), length));
    std::uint64_t key_differ = 0;
    for (std::size_t j = 0; j < length; ++j) {
      keys[j] = ordered_bits(points[run[j]].x + 0.0);
      key_differ |= keys[j] ^ keys[0];
      values[j] = run[j];
    }
    sort_by_code_sequential(keys, values, run_keys_scratch.data(), run_values_scratch.data(), length,
                            std::bit_width(key_differ));
    std::copy(values, values + length, run);
    for (std::size_t g = 0; g < length;) {
      std::size_t h = g + 1;
      while (h < length && keys[h] == keys[g]) ++h;
      if (h - g >= 2) std::sort(run + g, run + h, by_point);
      g = h;
    }
  }

  // One bucket too large for one thread: sorted by code on all threads, then its runs.
  void sort_big_bucket(std::size_t d) {
    auto& sorted = sites_.points;
    const std::size_t lo = bucket_start_[d], m = bucket_start_[d + 1] - lo;
    HostVector<std::uint64_t> codes;
    HostVector<std::int32_t> position, index;
    HostVector<Point2> points;
    resize_for_parallel_write(codes, m);
    resize_for_parallel_write(position, m);
    resize_for_parallel_write(index, m);
    resize_for_parallel_write(points, m);
    parallel_chunks(m, [&](std::size_t, std::size_t begin, std::size_t end) {
      for (std::size_t j = begin; j < end; ++j) {
        points[j] = sites_.points[lo + j];
        index[j] = sites_.input_index[lo + j];
        codes[j] = code_of(points[j]);
        position[j] = static_cast<std::int32_t>(j);
      }
    });
    sort_by_code(codes, position);
    parallel_chunks(m, [&](std::size_t, std::size_t begin, std::size_t end) {
      for (std::size_t k = begin; k < end; ++k) {
        sites_.points[lo + k] = points[position[k]];
        sites_.input_index[lo + k] = index[position[k]];
      }
    });
    // Its runs may cross chunk boundaries: their starts are marked first, then each chunk sorts
    // the runs that start in it (and only it touches them).
    const std::size_t hi = lo + m;
    HostVector<unsigned char> run_start(m);
    parallel_chunks(m, [&](std::size_t, std::size_t begin, std::size_t end) {
      for (std::size_t k = lo + begin; k < lo + end; ++k) run_start[k - lo] = k == lo || !same_code(k - 1, k);
    });
    parallel_chunks(m, [&](std::size_t, std::size_t begin, std::size_t end) {
      std::vector<std::pair<Point2, std::int32_t>> run;
      std::size_t repeats_here = 0;
      for (std::size_t k = lo + begin; k < lo + end; ++k) {
        if (!run_start[k - lo]) continue;
        std::size_t last = k + 1;
        while (last < hi && !run_start[last - lo]) ++last;
        if (last - k < 2) continue;
        run.clear();
        for (std::size_t j = k; j < last; ++j) run.emplace_back(sorted[j], sites_.input_index[j]);
        // Input indices rise along the run (the sort was stable): ties broken by them are the
        // stable order, and std::sort needs no buffer (kuzmin's runs are long: ~1/3 of its time).
        std::sort(run.begin(), run.end(), [&](const auto& a, const auto& b) {
          return point_less(a.first, b.first) || (!point_less(b.first, a.first) && a.second < b.second);
        });
        for (std::size_t j = k; j < last; ++j) {
          sorted[j] = run[j - k].first;
          sites_.input_index[j] = run[j - k].second;
          repeats_here += j > k && repeats_previous(j);
        }
      }
      if (repeats_here > 0) repeated_.fetch_add(repeats_here, std::memory_order_relaxed);
    });
  }

  bool same_code(std::size_t j, std::size_t k) const {
    const auto& sorted = sites_.points;
    return quantiser_.x(sorted[j].x) == quantiser_.x(sorted[k].x) && quantiser_.y(sorted[j].y) == quantiser_.y(sorted[k].y);
  }

  // Duplicates: position k repeats the point before it or is a new site; the first position
  // of a group of equal points represents the group.
  void merge_duplicates() {
    const std::size_t n = n_, chunks = chunks_;
    auto& sorted = sites_.points;
    std::vector<std::size_t> repeats(chunks + 1, 0);
    parallel_chunks(n, chunks, [&](std::size_t chunk, std::size_t begin, std::size_t end) {
      std::size_t count = 0;
      for (std::size_t k = begin; k < end; ++k) count += repeats_previous(k);
      repeats[chunk + 1] = count;
    });
    for (std::size_t c = 0; c < chunks; ++c) repeats[c + 1] += repeats[c];
    // Sites are the positions that repeat nothing, in order; chunk c's first one is site
    // begin - repeats[c].
    const std::size_t site_count = n - repeats[chunks];
    HostVector<Point2> points(site_count);
    HostVector<std::int32_t> input_index(site_count);
    parallel_chunks(n, chunks, [&](std::size_t chunk, std::size_t begin, std::size_t end) {
      std::size_t site = begin - repeats[chunk];
      std::size_t first = begin;  // the first position of k's group of equal points
      while (repeats_previous(first)) --first;
      for (std::size_t k = begin; k < end; ++k) {
        if (!repeats_previous(k)) first = k;
        sites_.representative[sites_.input_index[k]] = sites_.input_index[first];
        if (first == k) {
          points[site] = sorted[k];
          input_index[site] = sites_.input_index[k];
          ++site;
        }
      }
    });
    sites_.points = std::move(points);
    sites_.input_index = std::move(input_index);
  }

  std::span<const Point2> input_;
  const InputScan& scan_;
  const std::size_t n_, chunks_;
  const Quantiser quantiser_;
  const SplitPlan plan_;
  SiteSet sites_;
  std::vector<std::size_t> bucket_start_;
  std::atomic<std::size_t> repeated_{0};  // positions equal to the point before them
};

}  // namespace

SiteSet prepare_sites(std::span<const Point2> input) {
  const InputScan scan = scan_input(input);
  return SitePreparation(input, scan).run();
}

}  // namespace expanse::detail
