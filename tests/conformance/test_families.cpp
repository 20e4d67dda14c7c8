// Triangle-for-triangle equality with CGAL on every point family, at sizes from 3 up.
#include <catch2/catch.hpp>

#include <string>

#include "conformance.hpp"
#include "expanse/generate.hpp"
#include "support/test_points.hpp"

using namespace expanse;
using namespace expanse::conformance;

namespace {

const std::size_t sizes[] = {3, 4, 5, 10, 100, 1000, 10000, 100000};

void run_family(const test::Family& family, const Layout& layout = {}, std::size_t max_n = SIZE_MAX) {
  for (std::size_t n : sizes) {
    if (n > family.max_n || n > max_n) continue;
    for (std::uint64_t seed : {1u, 2u}) {
      if (seed > 1 && n >= 10000) continue;  // the big sizes once: time, not coverage, is short
      const auto points = family.generate(n, seed);
      expect_matches_cgal(std::string(family.name) + "-n" + std::to_string(n) + "-s" + std::to_string(seed),
                          points, options(layout));
    }
  }
}

const test::Family& family(const char* name) {
  for (const auto& f : test::families())
    if (std::string(f.name) == name) return f;
  throw std::logic_error(std::string("no test family ") + name);
}

}  // namespace

// One TEST_CASE per family, so a failure names the family and `-# [family]` can pick one.
#define FAMILY_CASE(name) \
  TEST_CASE("matches CGAL: " name, "[family]") { run_family(family(name)); }

FAMILY_CASE("uniform")
FAMILY_CASE("gaussian")
FAMILY_CASE("clusters")
FAMILY_CASE("kuzmin")
FAMILY_CASE("grid")
FAMILY_CASE("rotated_grid_exact")
FAMILY_CASE("rotated_grid_float")
FAMILY_CASE("decimal_grid")
FAMILY_CASE("lattice_circle")
FAMILY_CASE("collinear_plus_one")
FAMILY_CASE("duplicates")
FAMILY_CASE("grid_with_duplicates")
FAMILY_CASE("offset")
FAMILY_CASE("near_collinear")
FAMILY_CASE("thin_circle")
FAMILY_CASE("tiny")
FAMILY_CASE("huge")
FAMILY_CASE("tiny_grid")
FAMILY_CASE("huge_grid")
FAMILY_CASE("offset_grid")
FAMILY_CASE("square_boundary")
FAMILY_CASE("two_lines")
FAMILY_CASE("cross")
FAMILY_CASE("mixed_scale")

TEST_CASE("every test family is run", "[family]") {
  // A family added to test_points.cpp without a FAMILY_CASE above would silently go untested.
  CHECK(test::families().size() == 24);
}

TEST_CASE("matches CGAL with the paper's layout", "[family][paper]") {
  for (const char* name : {"uniform", "gaussian", "grid", "duplicates", "kuzmin"})
    run_family(family(name), Layout::paper(), 10000);
}

TEST_CASE("matches CGAL with unusual layouts", "[family][layout]") {
  Layout coarse = Layout::paper();
  coarse.blocks_per_side = 1;
  coarse.buckets_per_block_side = 2;
  Layout fine = Layout::paper();
  fine.blocks_per_side = 64;
  fine.buckets_per_block_side = 4;
  fine.halo_fraction = 0.0;
  Layout sparse;
  sparse.sites_per_bucket = 50.0;
  for (const Layout& layout : {coarse, fine, sparse}) {
    run_family(family("uniform"), layout, 10000);
    run_family(family("grid"), layout, 1000);
  }
}

TEST_CASE("matches CGAL on the library's own generator", "[family][generate]") {
  for (const auto& name : distribution_names())
    for (std::size_t n : {3, 10, 1000}) {
      const auto points = generate_points(name, n, 5);
      expect_matches_cgal("generate-" + name + "-n" + std::to_string(n), points, options());
    }
}

TEST_CASE("matches CGAL without neighbors", "[family]") {
  Options o = options();
  o.neighbors = false;
  expect_matches_cgal("uniform-no-neighbors", test::points::uniform(1000, 3), o);
}
