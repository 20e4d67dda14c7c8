// Input preparation: validation names the first bad point even when the pass runs in parallel
// chunks; duplicates keep their first occurrence; scaling is exact.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <string>

#include "expanse/error.hpp"
#include "expanse/generate.hpp"
#include "input/site_set.hpp"

using namespace expanse;
using namespace expanse::detail;

TEST_CASE("the first non-finite point is named, whichever chunk sees it", "[input]") {
  std::vector<Point2> points = generate_points("uniform", std::size_t{1} << 20, 5);
  points[700000].y = std::numeric_limits<double>::infinity();
  points[300001].x = std::numeric_limits<double>::quiet_NaN();
  try {
    prepare_sites(points);
    FAIL("no error");
  } catch (const Error& e) {
    CHECK(e.code() == ErrorCode::invalid_input);
    CHECK_THAT(e.what(), Catch::Contains("point 300001 "));
  }
}

TEST_CASE("large inputs merge duplicates to their first occurrence, sites in Morton order", "[input]") {
  std::vector<Point2> points = generate_points("uniform", 600000, 9);
  for (std::size_t i = 300000; i < points.size(); ++i) points[i] = points[i - 300000];
  const SiteSet sites = prepare_sites(points);
  REQUIRE(sites.size() == 300000);
  for (std::size_t i = 0; i < points.size(); ++i) {
    REQUIRE(sites.representative[i] == static_cast<std::int32_t>(i % 300000));
  }
  for (std::int32_t s = 0; s < sites.size(); ++s) {
    const Point2& original = points[sites.input_index[s]];
    REQUIRE(std::ldexp(original.x, sites.scale_exponent) == sites.points[s].x);
    REQUIRE(std::ldexp(original.y, sites.scale_exponent) == sites.points[s].y);
  }
}

TEST_CASE("the scan tells integer coordinates apart, and the sites keep it", "[input]") {
  // Large enough for several chunks, so every chunk's verdict counts.
  std::vector<expanse::Point2> lattice;
  for (int i = 0; i < 300000; ++i) lattice.push_back({double(i % 600) - 300.0, double(i / 600) * 4.0});
  CHECK(expanse::detail::scan_input(lattice).integer_coordinates);
  CHECK(expanse::detail::prepare_sites(lattice).integer_coordinates);
  for (const std::size_t at : {std::size_t{0}, lattice.size() / 2, lattice.size() - 1}) {
    std::vector<expanse::Point2> off = lattice;
    off[at].y += 0.5;
    INFO("a half at point " << at);
    CHECK_FALSE(expanse::detail::scan_input(off).integer_coordinates);
    CHECK_FALSE(expanse::detail::prepare_sites(off).integer_coordinates);
  }
  CHECK_FALSE(expanse::detail::scan_input(expanse::generate_points("uniform", 1000, 1)).integer_coordinates);
}
