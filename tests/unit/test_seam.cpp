// The seam-completion stage restores CGAL's mesh exactly from any correct partial mesh: regions
// deleted, strips along a block grid (what the paper's layout leaves open), random triangles.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>

#include "expanse/error.hpp"
#include "expanse/generate.hpp"
#include "grid/apex_search.hpp"
#include "grid/bucket_tree.hpp"
#include "hull/convex_hull.hpp"
#include "input/site_set.hpp"
#include "seam/adjacency_audit.hpp"
#include "seam/seam_completion.hpp"
#include "support/cgal_oracle.hpp"

using namespace expanse;
using namespace expanse::detail;

namespace {

struct Fixture {
  std::vector<Point2> points;
  SiteSet sites;
  Hull hull;
  std::vector<Triangle> oracle_sites;  // CGAL's triangles in site ids
  std::vector<Triangle> oracle_input;  // CGAL's triangles in input indices

  Fixture(const std::string& distribution, std::size_t n)
      : points(generate_points(distribution, n, 11)), sites(prepare_sites(points)), hull(convex_hull(sites)) {
    std::vector<std::int32_t> site_of(points.size(), -1);
    for (std::int32_t s = 0; s < sites.size(); ++s) site_of[sites.input_index[s]] = s;
    oracle_input = test::cgal_delaunay(points).triangles;
    for (const Triangle& t : oracle_input) oracle_sites.push_back({site_of[t[0]], site_of[t[1]], site_of[t[2]]});
  }

  // Keeps the oracle triangles `keep` accepts, completes, compares with CGAL: over the full
  // bucket tree and over one built on demand (what the pipeline uses for tiny seams).
  template <class Keep>
  void complete_and_compare(Keep&& keep, std::size_t* removed_out = nullptr) {
    PartialTriangulation kept;
    for (const Triangle& t : oracle_sites) {
      if (keep(t)) kept.triangles.push_back(t);
    }
    const std::size_t removed = oracle_sites.size() - kept.triangles.size();
    if (removed_out) *removed_out = removed;
    for (const bool on_demand : {false, true}) {
      INFO((on_demand ? "on-demand tree" : "full tree"));
      PartialTriangulation partial = kept;
      const BucketTree tree = on_demand ? BucketTree::on_demand(sites) : BucketTree(sites);
      complete(partial, tree, removed);
    }
    if (kept.triangles.empty()) return;
    // With the adjacency given and its open links listed (as the CUDA backend's audit lists
    // them): the seam starts from the list, and makes what it makes from a scan of the links.
    PartialTriangulation scanned = kept, listed = kept;
    scanned.neighbors = derive_neighbors(kept.triangles);
    listed.neighbors = scanned.neighbors;
    std::vector<std::int64_t> slots;
    for (std::size_t t = 0; t < listed.triangles.size(); ++t) {
      for (int k = 0; k < 3; ++k) {
        const Triangle& tri = listed.triangles[t];
        if (listed.neighbors[t][k] == no_neighbor && !hull.is_outer_edge(tri[(k + 1) % 3], tri[(k + 2) % 3]))
          slots.push_back(static_cast<std::int64_t>(3 * t) + k);
      }
    }
    listed.open_slots = std::move(slots);
    {
      INFO("open links listed");
      complete(listed, BucketTree(sites), removed);
    }
    complete_seam(sites, hull, BucketTree(sites), scanned);
    CHECK(listed.triangles == scanned.triangles);
    CHECK(listed.neighbors == scanned.neighbors);
  }

  void complete(PartialTriangulation& partial, const BucketTree& tree, std::size_t removed) {
    const SeamStats stats = complete_seam(sites, hull, tree, partial);
    CHECK(stats.triangles_made == removed);
    std::vector<Triangle> result;
    for (const Triangle& t : partial.triangles) {
      result.push_back({sites.input_index[t[0]], sites.input_index[t[1]], sites.input_index[t[2]]});
    }
    const test::Comparison comparison = test::compare_triangles(result, oracle_input);
    INFO(comparison.message);
    CHECK(comparison.equal);
    // Neighbours come back consistent: across edge k of t lies a triangle sharing that edge.
    REQUIRE(partial.neighbors.size() == partial.triangles.size());
    for (std::size_t t = 0; t < partial.triangles.size(); ++t) {
      for (int k = 0; k < 3; ++k) {
        const std::int32_t u = partial.neighbors[t][k];
        if (u == no_neighbor) continue;
        const std::int32_t x = partial.triangles[t][(k + 1) % 3], y = partial.triangles[t][(k + 2) % 3];
        const Triangle& other = partial.triangles[u];
        bool shares = false;
        for (int j = 0; j < 3; ++j) shares |= other[(j + 1) % 3] == y && other[(j + 2) % 3] == x;
        REQUIRE(shares);
      }
    }
  }

  Point2 centroid(const Triangle& t) const {
    const auto& p = sites.points;
    return {(p[t[0]].x + p[t[1]].x + p[t[2]].x) / 3, (p[t[0]].y + p[t[1]].y + p[t[2]].y) / 3};
  }
};

}  // namespace

TEST_CASE("seam stage grows the whole mesh from nothing (the CPU backend)", "[seam]") {
  for (const char* distribution : {"uniform", "gaussian", "grid", "circle"}) {
    Fixture f(distribution, 3000);
    f.complete_and_compare([](const Triangle&) { return false; });
  }
}

TEST_CASE("seam stage fills deleted regions", "[seam]") {
  for (const char* distribution : {"uniform", "kuzmin", "grid", "rotated_grid"}) {
    Fixture f(distribution, 5000);
    const Box& b = f.sites.bounds;
    const double cx = 0.5 * (b.min_x + b.max_x), cy = 0.5 * (b.min_y + b.max_y);
    const double r = 0.2 * (b.max_x - b.min_x);
    std::size_t removed = 0;
    // A central disk and a corner square.
    f.complete_and_compare(
        [&](const Triangle& t) {
          const Point2 c = f.centroid(t);
          const bool in_disk = std::hypot(c.x - cx, c.y - cy) < r;
          const bool in_corner = c.x < b.min_x + 0.15 * (b.max_x - b.min_x) && c.y < b.min_y + 0.15 * (b.max_y - b.min_y);
          return !in_disk && !in_corner;
        },
        &removed);
    CHECK(removed > 0);
  }
}

TEST_CASE("seam stage fills strips along a block grid", "[seam]") {
  for (const char* distribution : {"uniform", "gaussian", "grid"}) {
    Fixture f(distribution, 8000);
    const Box& b = f.sites.bounds;
    const int blocks = 8;
    const double w = (b.max_x - b.min_x) / blocks, h = (b.max_y - b.min_y) / blocks;
    // A triangle crossing a block boundary is what the paper's blocks leave to the CPU.
    const auto block_of = [&](const Point2& p) {
      const int i = std::min(blocks - 1, static_cast<int>((p.x - b.min_x) / w));
      const int j = std::min(blocks - 1, static_cast<int>((p.y - b.min_y) / h));
      return j * blocks + i;
    };
    std::size_t removed = 0;
    f.complete_and_compare(
        [&](const Triangle& t) {
          const int k = block_of(f.sites.points[t[0]]);
          return k == block_of(f.sites.points[t[1]]) && k == block_of(f.sites.points[t[2]]);
        },
        &removed);
    CHECK(removed > 0);
  }
}

TEST_CASE("seam stage restores random deletions", "[seam]") {
  for (const char* distribution : {"uniform", "clusters", "circle", "duplicates", "offset"}) {
    Fixture f(distribution, 4000);
    for (double fraction : {0.02, 0.5, 0.98}) {
      std::mt19937_64 rng(7);
      std::bernoulli_distribution drop(fraction);
      f.complete_and_compare([&](const Triangle&) { return !drop(rng); });
    }
  }
}

TEST_CASE("seam stage with a single triangle left", "[seam]") {
  Fixture f("uniform", 2000);
  const Triangle keep = f.oracle_sites[f.oracle_sites.size() / 2];
  f.complete_and_compare([&](const Triangle& t) { return t == keep; });
}

TEST_CASE("adjacency audit trusts consistent device adjacency and catches spurious open edges", "[seam]") {
  Fixture f("uniform", 3000);
  std::mt19937_64 rng(3);
  std::bernoulli_distribution drop(0.05);
  PartialTriangulation partial;
  for (const Triangle& t : f.oracle_sites) {
    if (!drop(rng)) partial.triangles.push_back(t);
  }
  partial.neighbors = derive_neighbors(partial.triangles);
  CHECK(adjacency_is_trustworthy(partial, f.hull));

  SECTION("a link cut on one side only") {
    for (auto& n : partial.neighbors) {
      if (n[0] != no_neighbor) {
        n[0] = no_neighbor;
        break;
      }
    }
    CHECK_FALSE(adjacency_is_trustworthy(partial, f.hull));
  }
  SECTION("a link cut on both sides: an interior edge claimed open") {
    for (std::size_t t = 0; t < partial.neighbors.size(); ++t) {
      const std::int32_t u = partial.neighbors[t][0];
      if (u == no_neighbor) continue;
      for (auto& back : partial.neighbors[u]) {
        if (back == static_cast<std::int32_t>(t)) back = no_neighbor;
      }
      partial.neighbors[t][0] = no_neighbor;
      break;
    }
    CHECK_FALSE(adjacency_is_trustworthy(partial, f.hull));
  }
  SECTION("a link to the wrong triangle") {
    partial.neighbors[10][1] = 11;
    CHECK_FALSE(adjacency_is_trustworthy(partial, f.hull));
  }
  SECTION("trusted adjacency completes to CGAL's mesh") {
    const BucketTree tree(f.sites);
    complete_seam(f.sites, f.hull, tree, partial);
    std::vector<Triangle> result;
    for (const Triangle& t : partial.triangles) {
      result.push_back({f.sites.input_index[t[0]], f.sites.input_index[t[1]], f.sites.input_index[t[2]]});
    }
    CHECK(test::compare_triangles(result, f.oracle_input).equal);
  }
}

TEST_CASE("seam stage refuses a listed open link that is linked", "[seam]") {
  Fixture f("uniform", 3000);
  PartialTriangulation partial;
  for (std::size_t t = 0; t < f.oracle_sites.size(); ++t) {
    if (t % 50 != 0) partial.triangles.push_back(f.oracle_sites[t]);
  }
  partial.neighbors = derive_neighbors(partial.triangles);
  std::size_t linked = 0;
  while (partial.neighbors[linked][0] == no_neighbor) ++linked;
  partial.open_slots = std::vector<std::int64_t>{static_cast<std::int64_t>(3 * linked)};  // not open: a bug
  try {
    complete_seam(f.sites, f.hull, BucketTree(f.sites), partial);
    FAIL("a linked edge listed as open was not refused");
  } catch (const Error& e) {
    CHECK(e.code() == ErrorCode::internal);
  }
}

TEST_CASE("apex searches around slivers stay local and exact (rotated float grid)", "[seam]") {
  // The 3-4-5 grid times 0.1: rounding leaves its rows a hair off straight, so the Delaunay mesh
  // is full of slivers whose circles are 10^10 times the domain. Every interior edge's apex
  // (CGAL's other triangle) must be found, each search testing a small part of the sites: a
  // sliver's circle taken from the rounded determinant once sent searches over every site.
  std::vector<Point2> points = generate_points("rotated_grid", 40000, 11);
  for (Point2& p : points) p = {0.1 * p.x, 0.1 * p.y};
  const SiteSet sites = prepare_sites(points);
  const Hull hull = convex_hull(sites);
  std::vector<std::int32_t> site_of(points.size(), -1);
  for (std::int32_t s = 0; s < sites.size(); ++s) site_of[sites.input_index[s]] = s;
  std::map<std::pair<std::int32_t, std::int32_t>, std::int32_t> apex_of;  // CGAL: a->b has apex c on its left
  for (const Triangle& t : test::cgal_delaunay(points).triangles)
    for (int k = 0; k < 3; ++k) apex_of[{site_of[t[k]], site_of[t[(k + 1) % 3]]}] = site_of[t[(k + 2) % 3]];
  const BucketTree tree = BucketTree::on_demand(sites);
  ApexSearch search(sites, tree);
  std::uint64_t most = 0, searches = 0;
  for (const auto& [edge, apex] : apex_of) {
    const std::uint64_t before = search.candidates_tested();
    REQUIRE(search.apex_search(edge.first, edge.second) == apex);
    most = std::max(most, search.candidates_tested() - before);
    ++searches;
  }
  INFO("most candidates in one search: " << most << ", mean " << search.candidates_tested() / searches);
  CHECK(most < static_cast<std::uint64_t>(sites.size()) / 20);
  CHECK(search.candidates_tested() < 40 * searches);
}
