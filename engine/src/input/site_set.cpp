#include "input/site_set.hpp"

#include <cfloat>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include "expanse/error.hpp"

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

// Open-addressing set of coordinate pairs -> first site id; value equality (0.0 == -0.0).
class PointIndex {
 public:
  explicit PointIndex(std::size_t n) {
    std::size_t capacity = 16;
    while (capacity < 2 * n) capacity <<= 1;
    slots_.assign(capacity, -1);
    mask_ = capacity - 1;
  }
  // Returns the site already holding p, or inserts `site` and returns it.
  std::int32_t find_or_insert(const Point2& p, std::int32_t site, const std::vector<Point2>& pts) {
    std::size_t slot = hash(p) & mask_;
    while (true) {
      const std::int32_t held = slots_[slot];
      if (held < 0) {
        slots_[slot] = site;
        return site;
      }
      if (pts[held].x == p.x && pts[held].y == p.y) return held;
      slot = (slot + 1) & mask_;
    }
  }

 private:
  static std::uint64_t bits(double v) {
    v += 0.0;  // -0.0 -> +0.0, so equal values hash alike
    std::uint64_t b;
    std::memcpy(&b, &v, sizeof b);
    return b;
  }
  static std::size_t hash(const Point2& p) {
    std::uint64_t h = bits(p.x) * 0x9E3779B97F4A7C15ull ^ (bits(p.y) + 0x7F4A7C159E3779B9ull);
    h ^= h >> 29;
    h *= 0xBF58476D1CE4E5B9ull;
    h ^= h >> 32;
    return static_cast<std::size_t>(h);
  }
  std::vector<std::int32_t> slots_;
  std::size_t mask_ = 0;
};

}  // namespace

SiteSet prepare_sites(std::span<const Point2> input) {
  if (input.size() > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max())) {
    throw Error(ErrorCode::too_large, "at most 2^31 - 1 points are supported, got " +
                                          std::to_string(input.size()));
  }
  double max_abs = 0.0;
  double min_nonzero_abs = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < input.size(); ++i) {
    const Point2& p = input[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y)) throw_non_finite(i, p);
    for (double v : {std::fabs(p.x), std::fabs(p.y)}) {
      if (v > max_abs) max_abs = v;
      if (v != 0.0 && v < min_nonzero_abs) min_nonzero_abs = v;
    }
  }

  SiteSet sites;
  sites.scale_exponent = exact_scale_exponent(max_abs, min_nonzero_abs);
  sites.representative.resize(input.size());
  sites.points.reserve(input.size());
  sites.input_index.reserve(input.size());

  PointIndex index(input.size());
  for (std::size_t i = 0; i < input.size(); ++i) {
    const Point2 scaled{std::ldexp(input[i].x, sites.scale_exponent),
                        std::ldexp(input[i].y, sites.scale_exponent)};
    const auto next = static_cast<std::int32_t>(sites.points.size());
    sites.points.push_back(scaled);  // provisional; popped again if it is a duplicate
    const std::int32_t site = index.find_or_insert(scaled, next, sites.points);
    if (site != next) {
      sites.points.pop_back();
      sites.representative[i] = sites.input_index[site];
    } else {
      sites.input_index.push_back(static_cast<std::int32_t>(i));
      sites.representative[i] = static_cast<std::int32_t>(i);
    }
  }

  if (!sites.points.empty()) {
    Box box{sites.points[0].x, sites.points[0].y, sites.points[0].x, sites.points[0].y};
    for (const Point2& p : sites.points) {
      box.min_x = std::min(box.min_x, p.x);
      box.max_x = std::max(box.max_x, p.x);
      box.min_y = std::min(box.min_y, p.y);
      box.max_y = std::max(box.max_y, p.y);
    }
    sites.bounds = box;
  }
  return sites;
}

}  // namespace expanse::detail
