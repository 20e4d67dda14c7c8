// The named point distributions of `expanse generate`, the tests and the benchmarks.
#include <algorithm>
#include <cmath>
#include <string>

#include "expanse/error.hpp"
#include "expanse/generate.hpp"
#include "generate/lattice_circle.hpp"
#include "generate/random.hpp"

namespace expanse {
namespace {

using generate_detail::Random;
using Points = std::vector<Point2>;

void uniform(Points& out, std::size_t n, Random& r) {
  for (std::size_t i = 0; i < n; ++i) out.push_back({r.uniform(), r.uniform()});
}

// The paper's non-uniform set (Fig. IV.5): two gaussian clusters of equal size.
void gaussian(Points& out, std::size_t n, Random& r) {
  for (std::size_t i = 0; i < n; ++i) {
    const double c = (i % 2 == 0) ? 0.3 : 0.7;
    out.push_back({c + 0.08 * r.normal(), c + 0.08 * r.normal()});
  }
}

void clusters(Points& out, std::size_t n, Random& r) {
  const std::size_t k = std::clamp<std::size_t>(n / 100, 1, 10000);
  const double sigma = 0.05 / std::sqrt(static_cast<double>(k));
  Points centres;
  uniform(centres, k, r);
  for (std::size_t i = 0; i < n; ++i) {
    const Point2 c = centres[r.below(k)];
    out.push_back({c.x + sigma * r.normal(), c.y + sigma * r.normal()});
  }
}

std::size_t grid_side(std::size_t n) {
  auto side = static_cast<std::size_t>(std::sqrt(static_cast<double>(n)));
  while (side * side < n) ++side;
  return std::max<std::size_t>(side, 1);
}

// Row-major integer grid, the last row partly filled; every 4 neighbours are cocircular.
void grid(Points& out, std::size_t n, Random&) {
  const std::size_t side = grid_side(n);
  for (std::size_t i = 0; i < n; ++i) {
    out.push_back({static_cast<double>(i % side), static_cast<double>(i / side)});
  }
}

// The grid turned by the 3-4-5 angle and scaled by 5: still integer, so still exactly
// cocircular, but no longer axis-aligned.
void rotated_grid(Points& out, std::size_t n, Random& r) {
  grid(out, n, r);
  for (Point2& p : out) p = {3.0 * p.x - 4.0 * p.y, 4.0 * p.x + 3.0 * p.y};
}

// n - 1 integer points exactly on one circle, and its centre.
void circle(Points& out, std::size_t n, Random& r) {
  if (n == 0) return;
  out.push_back({0.0, 0.0});
  const std::size_t m = n - 1;
  if (m == 0) return;
  if (auto lattice = generate_detail::lattice_circle(m)) {
    generate_detail::shuffle(lattice->data(), lattice->size(), r);
    for (std::size_t i = 0; i < m; ++i) {
      out.push_back({static_cast<double>((*lattice)[i].first), static_cast<double>((*lattice)[i].second)});
    }
  } else {
    // More points than any exactly representable lattice circle holds: nearly cocircular.
    for (std::size_t i = 0; i < m; ++i) {
      double x, y;
      r.on_circle(x, y);
      out.push_back({x, y});
    }
  }
  generate_detail::shuffle(out.data(), out.size(), r);
}

void disk(Points& out, std::size_t n, Random& r) {
  for (std::size_t i = 0; i < n; ++i) {
    double x, y;
    r.in_disk(x, y);
    out.push_back({x, y});
  }
}

// Kuzmin's disk: surface density ~ (1 + r^2)^(-3/2), mass within r = 1 - 1/sqrt(1 + r^2),
// inverted exactly (sqrt only). Very dense centre, very sparse far tail.
void kuzmin(Points& out, std::size_t n, Random& r) {
  for (std::size_t i = 0; i < n; ++i) {
    const double u = r.uniform();
    const double q = 1.0 - u;  // in (0, 1]
    const double radius = std::sqrt(std::max(0.0, 1.0 / (q * q) - 1.0));
    double x, y;
    r.on_circle(x, y);
    out.push_back({radius * x, radius * y});
  }
}

// y = 2x holds exactly for every point (doubling is exact), so all are collinear.
void line(Points& out, std::size_t n, Random& r) {
  for (std::size_t i = 0; i < n; ++i) {
    const double t = r.uniform();
    out.push_back({t, 2.0 * t});
  }
}

// The worst case for growing fronts: n - 1 collinear integer points and one apex above the
// middle, which every triangle shares.
void collinear_plus_one(Points& out, std::size_t n, Random& r) {
  if (n == 0) return;
  for (std::size_t i = 0; i + 1 < n; ++i) out.push_back({static_cast<double>(i), 0.0});
  out.push_back({static_cast<double>((n - 1) / 2) + 0.5, 1.0});
  generate_detail::shuffle(out.data(), out.size(), r);
}

// A quarter of the points are distinct; the rest repeat them exactly.
void duplicates(Points& out, std::size_t n, Random& r) {
  const std::size_t distinct = std::max<std::size_t>(1, n / 4);
  uniform(out, std::min(n, distinct), r);
  while (out.size() < n) out.push_back(out[r.below(distinct)]);
  generate_detail::shuffle(out.data(), out.size(), r);
}

// Far from the origin with a tiny spread: only ~67 representable values per axis, so the
// points snap to a fine lattice with many cocircular quadruples and duplicates.
void offset(Points& out, std::size_t n, Random& r) {
  for (std::size_t i = 0; i < n; ++i) {
    out.push_back({1e8 + 1e-6 * r.uniform(), 1e8 + 1e-6 * r.uniform()});
  }
}

// Within a few ulps of the line y = 2x: orientation tests sit at the rounding level.
void near_collinear(Points& out, std::size_t n, Random& r) {
  for (std::size_t i = 0; i < n; ++i) {
    const double t = r.uniform();
    out.push_back({t, 2.0 * t + 0x1.0p-50 * (r.uniform() - 0.5)});
  }
}

// An annulus of relative width 1e-9 around the unit circle: incircle tests near zero.
void thin_circle(Points& out, std::size_t n, Random& r) {
  for (std::size_t i = 0; i < n; ++i) {
    double x, y;
    r.on_circle(x, y);
    const double s = 1.0 + 1e-9 * (r.uniform() - 0.5);
    out.push_back({s * x, s * y});
  }
}

// Degree-4 predicate terms underflow (tiny) or overflow (huge) unless the engine rescales.
void tiny(Points& out, std::size_t n, Random& r) {
  for (std::size_t i = 0; i < n; ++i) out.push_back({1e-100 * r.uniform(), 1e-100 * r.uniform()});
}

void huge(Points& out, std::size_t n, Random& r) {
  for (std::size_t i = 0; i < n; ++i) out.push_back({1e100 * r.uniform(), 1e100 * r.uniform()});
}

struct Distribution {
  const char* name;
  void (*make)(Points&, std::size_t, Random&);
  const char* description;
};

constexpr Distribution kDistributions[] = {
    {"uniform", uniform, "uniform in the unit square"},
    {"gaussian", gaussian, "two gaussian clusters (the paper's non-uniform set)"},
    {"clusters", clusters, "many small gaussian clusters"},
    {"grid", grid, "integer grid, row by row"},
    {"rotated_grid", rotated_grid, "integer grid turned by the 3-4-5 angle"},
    {"circle", circle, "integer points exactly on one circle, plus its centre"},
    {"disk", disk, "uniform in the unit disk"},
    {"kuzmin", kuzmin, "Kuzmin disk: dense centre, sparse tail"},
    {"line", line, "collinear points on y = 2x"},
    {"collinear_plus_one", collinear_plus_one, "n-1 collinear points and one apex"},
    {"duplicates", duplicates, "uniform, each point repeated about 4 times"},
    {"offset", offset, "1e8 offset with 1e-6 spread"},
    {"near_collinear", near_collinear, "within ulps of a line"},
    {"thin_circle", thin_circle, "annulus of relative width 1e-9"},
    {"tiny", tiny, "uniform in [0, 1e-100)^2"},
    {"huge", huge, "uniform in [0, 1e100)^2"},
};

}  // namespace

std::vector<std::string> distribution_names() {
  std::vector<std::string> names;
  for (const Distribution& d : kDistributions) names.emplace_back(d.name);
  return names;
}

std::string_view describe_distribution(std::string_view name) {
  for (const Distribution& d : kDistributions) {
    if (name == d.name) return d.description;
  }
  return {};
}

std::vector<Point2> generate_points(std::string_view distribution, std::size_t n,
                                    std::uint64_t seed) {
  if (n > static_cast<std::size_t>(INT32_MAX)) {
    throw Error(ErrorCode::invalid_argument, "at most 2^31 - 1 points can be generated");
  }
  for (const Distribution& d : kDistributions) {
    if (distribution != d.name) continue;
    Random random(seed);
    Points points;
    points.reserve(n);
    d.make(points, n, random);
    return points;
  }
  std::string valid;
  for (const Distribution& d : kDistributions) valid += (valid.empty() ? "" : ", ") + std::string(d.name);
  throw Error(ErrorCode::invalid_argument,
              "unknown distribution '" + std::string(distribution) + "'; valid: " + valid);
}

}  // namespace expanse
