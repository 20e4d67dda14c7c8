// convex_hull() drops sites that are certainly strictly inside the polygon of its eight extreme
// sites before the monotone chain (an inner box, a grid of cells inside the polygon, the
// orientation filter, then exact tests). Whatever path a site takes, the hull must equal the
// monotone chain over every site, collinear hull sites included. convex_hull_of_input() runs the
// same filter and chain over the raw input: it must name the same hull by input indices.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <map>
#include <numeric>
#include <string>
#include <utility>

#include "expanse/generate.hpp"
#include "hull/convex_hull.hpp"
#include "input/parallel.hpp"
#include "input/site_set.hpp"
#include "predicates/predicates.hpp"

using namespace expanse;
using namespace expanse::detail;

namespace {

struct Threads {
  explicit Threads(std::size_t n) { set_host_threads(n); }
  ~Threads() { set_host_threads(0); }
};

// The monotone chain over all sites, no filter: pop only on a strict right turn.
std::vector<std::int32_t> reference_hull(const SiteSet& sites, bool& collinear) {
  const auto& p = sites.points;
  std::vector<std::int32_t> order(p.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](std::int32_t a, std::int32_t b) {
    return p[a].x < p[b].x || (p[a].x == p[b].x && p[a].y < p[b].y);
  });
  collinear = std::all_of(order.begin(), order.end(),
                          [&](std::int32_t i) { return orient2d(p[order.front()], p[order.back()], p[i]) == 0; });
  if (collinear) return order;
  std::vector<std::int32_t> chain;
  const auto extend = [&](std::int32_t site, std::size_t floor) {
    while (chain.size() >= floor + 2 && orient2d(p[chain[chain.size() - 2]], p[chain.back()], p[site]) < 0) {
      chain.pop_back();
    }
    chain.push_back(site);
  };
  for (std::int32_t site : order) extend(site, 0);
  const std::size_t lower = chain.size();
  for (auto it = order.rbegin() + 1; it != order.rend(); ++it) extend(*it, lower - 1);
  chain.pop_back();
  return chain;
}

void check_hull(const std::vector<Point2>& points) {
  const SiteSet sites = prepare_sites(points);
  bool collinear = false;
  const std::vector<std::int32_t> expected = reference_hull(sites, collinear);
  for (std::size_t threads : {1, 2, 7}) {
    INFO(threads << " threads");
    Threads use(threads);
    const Hull hull = convex_hull(sites);
    CHECK(hull.collinear == collinear);
    CHECK(hull.sites == expected);
    if (collinear) continue;
    std::vector<std::int32_t> predecessor(static_cast<std::size_t>(sites.size()), -1);
    for (std::size_t k = 0; k < expected.size(); ++k) {
      predecessor[expected[k]] = expected[(k + expected.size() - 1) % expected.size()];
    }
    CHECK(std::equal(hull.predecessor.begin(), hull.predecessor.end(), predecessor.begin(), predecessor.end()));
  }
}

// convex_hull(prepare_sites(points)), its sites named by input index.
InputHull hull_through_sites(const std::vector<Point2>& points) {
  const SiteSet sites = prepare_sites(points);
  const Hull hull = convex_hull(sites);
  InputHull named;
  named.collinear = hull.collinear;
  for (std::int32_t s : hull.sites) named.sites.push_back(sites.input_index[s]);
  return named;
}

// convex_hull_of_input on several thread counts against hull_through_sites; returns it.
InputHull check_input_hull(const std::vector<Point2>& points) {
  const InputHull expected = hull_through_sites(points);
  const InputScan scan = scan_input(points);
  InputHull found;
  for (std::size_t threads : {1, 2, 7}) {
    INFO(threads << " threads");
    Threads use(threads);
    found = convex_hull_of_input(points, scan);
    CHECK(found.collinear == expected.collinear);
    CHECK(found.sites == expected.sites);
  }
  return found;
}

// Input index of the first occurrence of each distinct point (-0.0 as 0.0): its representative.
std::map<std::pair<double, double>, std::int32_t> first_occurrences(const std::vector<Point2>& points) {
  std::map<std::pair<double, double>, std::int32_t> first;
  for (std::size_t i = 0; i < points.size(); ++i) {
    first.emplace(std::pair{points[i].x + 0.0, points[i].y + 0.0}, static_cast<std::int32_t>(i));
  }
  return first;
}

// A deterministic shuffle (its own generator: the same order everywhere).
void shuffle(std::vector<Point2>& points, std::uint64_t seed) {
  for (std::size_t i = points.size(); i > 1; --i) {
    seed = seed * 6364136223846793005ull + 1442695040888963407ull;
    std::swap(points[i - 1], points[(seed >> 33) % i]);
  }
}

// The integer lattice [0, k]^2 times `unit`, every point `copies` times, shuffled; with
// corners_first, one copy of each corner leads (the extremes' polygon is then the square, so
// the filter runs; else ties among the extremes usually leave it unusable). Returns the points
// and, through `expected`, the hull: CCW from the origin, every lattice point of the boundary,
// each by its first input index.
std::vector<Point2> lattice_square(int k, double unit, int copies, bool corners_first, std::vector<std::int32_t>& expected) {
  std::vector<Point2> points;
  for (int copy = 0; copy < copies; ++copy) {
    for (int i = 0; i <= k; ++i) {
      for (int j = 0; j <= k; ++j) points.push_back({i * unit, j * unit});
    }
  }
  shuffle(points, static_cast<std::uint64_t>(k * 31 + copies));
  if (corners_first) {
    const double far = k * unit;
    for (const Point2 corner : {Point2{0, 0}, Point2{far, 0}, Point2{far, far}, Point2{0, far}}) {
      points.insert(points.begin(), corner);
    }
  }
  const auto first = first_occurrences(points);
  const auto at = [&](int i, int j) { return first.at({i * unit, j * unit}); };
  expected.clear();
  for (int i = 0; i < k; ++i) expected.push_back(at(i, 0));
  for (int j = 0; j < k; ++j) expected.push_back(at(k, j));
  for (int i = k; i > 0; --i) expected.push_back(at(i, k));
  for (int j = k; j > 0; --j) expected.push_back(at(0, j));
  return points;
}

}  // namespace

TEST_CASE("hull: the monotone chain over every site, for every distribution", "[hull]") {
  for (const char* distribution : {"uniform", "gaussian", "clusters", "grid", "rotated_grid", "circle", "disk",
                                   "kuzmin", "line", "collinear_plus_one", "duplicates", "offset", "near_collinear",
                                   "thin_circle", "tiny", "huge"}) {
    for (std::size_t n : {std::size_t{1000}, std::size_t{300000}}) {
      INFO(distribution << ", n = " << n);
      check_hull(generate_points(distribution, n, 5));
    }
  }
}

TEST_CASE("hull: lattice bands whose sides are full of collinear hull sites (the grid filter's path)", "[hull]") {
  // A diagonal band of integer points: the box of the extremes is tiny, so the cells inside the
  // polygon do the filtering, and many sites lie exactly on hull edges near those cells.
  std::vector<Point2> band;
  for (int x = 0; x <= 3000; ++x) {
    for (int y = x - 40; y <= x + 40; ++y) band.push_back({static_cast<double>(x), static_cast<double>(y)});
  }
  check_hull(band);
  // Two diagonal clusters far apart, joined by a sparse line of points on the diagonal.
  std::vector<Point2> clusters;
  for (int cluster = 0; cluster < 2; ++cluster) {
    const int c = cluster * 5000;
    for (int x = -150; x <= 150; ++x) {
      for (int y = -150; y <= 150; ++y) {
        if (x * x + y * y <= 150 * 150) clusters.push_back({static_cast<double>(c + x), static_cast<double>(c + y)});
      }
    }
  }
  for (int t = 0; t <= 5000; t += 7) clusters.push_back({static_cast<double>(t), static_cast<double>(t)});
  check_hull(clusters);
}

TEST_CASE("hull of the input: convex_hull(prepare_sites) by input index, for every distribution", "[hull]") {
  for (const std::string& distribution : distribution_names()) {
    for (std::size_t n : {std::size_t{10}, std::size_t{1000}, std::size_t{150000}}) {
      INFO(distribution << ", n = " << n);
      check_input_hull(generate_points(distribution, n, 7));
    }
  }
  // The lattice bands of the grid filter's test above.
  std::vector<Point2> band;
  for (int x = 0; x <= 3000; ++x) {
    for (int y = x - 40; y <= x + 40; ++y) band.push_back({static_cast<double>(x), static_cast<double>(y)});
  }
  check_input_hull(band);
}

TEST_CASE("hull of the input: duplicates of hull vertices and collinear hull sites are named by their first index", "[hull]") {
  for (const bool corners_first : {true, false}) {
    for (const int copies : {1, 3}) {
      INFO("corners first: " << corners_first << ", copies: " << copies);
      std::vector<std::int32_t> expected;
      const std::vector<Point2> points = lattice_square(300, 1.0, copies, corners_first, expected);
      const InputHull hull = check_input_hull(points);
      CHECK_FALSE(hull.collinear);
      CHECK(hull.sites == expected);
    }
  }
  // Many copies of a few points around a dense interior; the copies' first indices lie in the
  // middle of the input, several copies of each are inside other chunks.
  std::vector<Point2> points = generate_points("uniform", 200000, 3);
  for (Point2& p : points) p = {0.25 + 0.5 * p.x, 0.25 + 0.5 * p.y};  // inside [0.25, 0.75]^2
  const std::vector<Point2> ring = {{0, 0}, {0.5, 0}, {1, 0}, {1, 1}, {0.5, 1}, {0, 1}, {0, 0.5}, {0.5, 0.5}};
  for (std::size_t copy = 0; copy < 40; ++copy) {
    for (std::size_t r = 0; r < ring.size(); ++r) points[(copy * 4999 + r * 17 + 100003) % points.size()] = ring[r];
  }
  const auto first = first_occurrences(points);
  const auto at = [&](double x, double y) { return first.at({x, y}); };
  const InputHull hull = check_input_hull(points);
  CHECK_FALSE(hull.collinear);
  CHECK(hull.sites == std::vector<std::int32_t>{at(0, 0), at(0.5, 0), at(1, 0), at(1, 1), at(0.5, 1), at(0, 1), at(0, 0.5)});
}

TEST_CASE("hull of the input: degenerate inputs (empty, one point repeated, two points, one line)", "[hull]") {
  {
    const InputHull hull = convex_hull_of_input({}, scan_input({}));
    CHECK(hull.sites.empty());
    CHECK_FALSE(hull.collinear);
    CHECK(hull_through_sites({}).sites.empty());
    CHECK_FALSE(hull_through_sites({}).collinear);
  }
  {
    const std::vector<Point2> same(100000, Point2{1.5, -2});
    const InputHull hull = check_input_hull(same);
    CHECK(hull.collinear);
    CHECK(hull.sites == std::vector<std::int32_t>{0});
  }
  {
    std::vector<Point2> two;
    for (int i = 0; i < 100001; ++i) two.push_back(i % 3 == 2 ? Point2{-1, 7} : Point2{3, -5});
    const InputHull hull = check_input_hull(two);
    CHECK(hull.collinear);
    CHECK(hull.sites == std::vector<std::int32_t>{2, 0});
  }
  // Lines: a diagonal, a steeper one, a horizontal and a vertical one; every distinct point in
  // lexicographic order, by its first index, copies everywhere.
  const auto line = [](double x0, double y0, double dx, double dy) {
    std::vector<Point2> points;
    for (int copy = 0; copy < 2; ++copy) {
      for (int t = -60000; t <= 60000; t += copy + 1) points.push_back({x0 + t * dx, y0 + t * dy});
    }
    shuffle(points, 11);
    return points;
  };
  for (const auto& [dx, dy] : {std::pair{1.0, 1.0}, std::pair{-1.0, 3.0}, std::pair{0.5, 0.0}, std::pair{0.0, -2.0}}) {
    INFO("direction " << dx << ", " << dy);
    const std::vector<Point2> points = line(5, -3, dx, dy);
    const auto first = first_occurrences(points);
    std::vector<std::int32_t> expected;
    for (const auto& [point, index] : first) expected.push_back(index);  // the map's order is (x, y)
    const InputHull hull = check_input_hull(points);
    CHECK(hull.collinear);
    CHECK(hull.sites == expected);
  }
}

TEST_CASE("hull of the input: tiny, subnormal and huge coordinates, negative zero", "[hull]") {
  for (const double unit : {0x1p-1000, 1e-300, std::numeric_limits<double>::denorm_min(), 0x1p+1000, 1e300}) {
    INFO("unit " << unit);
    std::vector<std::int32_t> expected;
    const std::vector<Point2> points = lattice_square(200, unit, 2, true, expected);
    const InputHull hull = check_input_hull(points);
    CHECK_FALSE(hull.collinear);
    CHECK(hull.sites == expected);
    std::vector<Point2> spread = generate_points("uniform", 100000, 9);
    for (Point2& p : spread) p = {p.x * unit, p.y * unit};
    check_input_hull(spread);
  }
  // -0.0 equals 0.0: the first of (0, 0), (-0, 0), (0, -0), (-0, -0) names the site.
  std::vector<Point2> points = {{1, 0}, {0.5, 0.5}, {-0.0, -0.0}, {1, 1}, {0, 1}, {0.0, 0.0}, {-0.0, 0.0}, {0.0, -0.0}, {-0.0, 1}};
  InputHull hull = check_input_hull(points);
  CHECK(hull.sites == std::vector<std::int32_t>{2, 0, 3, 4});
  points[2] = {0.25, 0.25};  // now (0, 0) first at 5; (-0, 1) after (0, 1): named 4
  hull = check_input_hull(points);
  CHECK(hull.sites == std::vector<std::int32_t>{5, 0, 3, 4});
}
