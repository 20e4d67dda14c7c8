#include "input/site_set.hpp"

#include <cfloat>
#include <cmath>
#include <algorithm>
#include <limits>
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

}  // namespace

SiteSet prepare_sites(std::span<const Point2> input) {
  if (input.size() > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max())) {
    throw Error(ErrorCode::too_large, "at most 2^31 - 1 points are supported, got " +
                                          std::to_string(input.size()));
  }
  // Validation and the magnitude range, per chunk; chunk order makes the first bad point the
  // one reported.
  const std::size_t n = input.size();
  struct Range {
    double max_abs = 0.0;
    double min_nonzero_abs = std::numeric_limits<double>::infinity();
  };
  std::vector<Range> ranges(chunk_count(n));
  parallel_chunks(n, [&](std::size_t chunk, std::size_t begin, std::size_t end) {
    Range r;
    for (std::size_t i = begin; i < end; ++i) {
      const Point2& p = input[i];
      if (!std::isfinite(p.x) || !std::isfinite(p.y)) throw_non_finite(i, p);
      for (double v : {std::fabs(p.x), std::fabs(p.y)}) {
        if (v > r.max_abs) r.max_abs = v;
        if (v != 0.0 && v < r.min_nonzero_abs) r.min_nonzero_abs = v;
      }
    }
    ranges[chunk] = r;
  });
  double max_abs = 0.0;
  double min_nonzero_abs = std::numeric_limits<double>::infinity();
  for (const Range& r : ranges) {
    max_abs = std::max(max_abs, r.max_abs);
    min_nonzero_abs = std::min(min_nonzero_abs, r.min_nonzero_abs);
  }

  SiteSet sites;
  sites.scale_exponent = exact_scale_exponent(max_abs, min_nonzero_abs);
  std::vector<Point2> scaled(n);
  std::vector<Box> boxes(ranges.size());
  parallel_chunks(n, [&](std::size_t chunk, std::size_t begin, std::size_t end) {
    Box box{};
    for (std::size_t i = begin; i < end; ++i) {
      scaled[i] = {std::ldexp(input[i].x, sites.scale_exponent), std::ldexp(input[i].y, sites.scale_exponent)};
      if (i == begin) box = {scaled[i].x, scaled[i].y, scaled[i].x, scaled[i].y};
      box.min_x = std::min(box.min_x, scaled[i].x);
      box.max_x = std::max(box.max_x, scaled[i].x);
      box.min_y = std::min(box.min_y, scaled[i].y);
      box.max_y = std::max(box.max_y, scaled[i].y);
    }
    boxes[chunk] = box;
  });
  Box box = boxes.empty() ? Box{} : boxes[0];
  for (const Box& b : boxes) {
    box.min_x = std::min(box.min_x, b.min_x);
    box.max_x = std::max(box.max_x, b.max_x);
    box.min_y = std::min(box.min_y, b.min_y);
    box.max_y = std::max(box.max_y, b.max_y);
  }
  sites.bounds = box;

  // Morton order, stable: equal points share a code, so each group of duplicates ends up in one
  // run of equal codes, its smallest input index first.
  const Quantiser quantiser(box);
  std::vector<std::uint64_t> codes(n);
  std::vector<std::int32_t> order(n);
  parallel_chunks(n, [&](std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      codes[i] = morton_code(quantiser.x(scaled[i].x), quantiser.y(scaled[i].y));
      order[i] = static_cast<std::int32_t>(i);
    }
  });
  sort_by_code(codes, order);

  // Gather into sorted order (the random reads happen here, spread over the threads), then
  // merge duplicates in one sequential pass and scatter the representatives back.
  std::vector<Point2> sorted(n);
  parallel_chunks(n, [&](std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t k = begin; k < end; ++k) sorted[k] = scaled[order[k]];
  });
  std::vector<Point2>().swap(scaled);
  std::vector<std::int32_t> representative_of_sorted(n);
  sites.points.reserve(n);
  sites.input_index.reserve(n);
  std::size_t run_start_site = 0;  // first site of the current run of equal codes
  for (std::size_t k = 0; k < n; ++k) {
    if (k == 0 || codes[k] != codes[k - 1]) run_start_site = sites.points.size();
    const std::int32_t i = order[k];
    const Point2 p = sorted[k];
    std::int32_t representative = i;
    for (std::size_t s = run_start_site; s < sites.points.size(); ++s) {  // runs are tiny
      if (sites.points[s].x == p.x && sites.points[s].y == p.y) {
        representative = sites.input_index[s];
        break;
      }
    }
    representative_of_sorted[k] = representative;
    if (representative == i) {
      sites.points.push_back(p);
      sites.input_index.push_back(i);
    }
  }
  sites.representative.resize(n);
  parallel_chunks(n, [&](std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t k = begin; k < end; ++k) sites.representative[order[k]] = representative_of_sorted[k];
  });
  return sites;
}

}  // namespace expanse::detail
