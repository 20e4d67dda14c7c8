// The host stages run on all threads; their results must not depend on how many. Each stage is
// checked at sizes that split the work (chunks of 2^16 items and up) against a plain
// sequential version written here, with 1, 2 and 7 threads.
#include <catch2/catch.hpp>

#include <algorithm>
#include <atomic>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <mutex>
#include <numeric>
#include <random>
#include <set>
#include <stdexcept>
#include <string>
#include <thread>

#include "expanse/error.hpp"
#include "expanse/generate.hpp"
#include "grid/apex_search.hpp"
#include "grid/bucket_tree.hpp"
#include "hull/convex_hull.hpp"
#include "input/morton.hpp"
#include "input/parallel.hpp"
#include "input/site_set.hpp"
#include "pipeline/output.hpp"
#include "seam/adjacency_audit.hpp"
#include "seam/seam_completion.hpp"
#include "support/cgal_oracle.hpp"
#include "support/tuning.hpp"

using namespace expanse;
using namespace expanse::detail;

namespace {

constexpr std::size_t thread_counts[] = {1, 2, 7};

// Restores the default thread count when a test ends, however it ends.
struct Threads {
  explicit Threads(std::size_t n) { set_host_threads(n); }
  ~Threads() { set_host_threads(0); }
};

// prepare_sites as it was written sequentially: scale, stable sort by Morton code (and by (x, y)
// among equal codes), merge runs of equal points.
void check_against_sequential(const std::vector<Point2>& input, const SiteSet& sites) {
  const std::size_t n = input.size();
  std::vector<Point2> scaled(n);
  for (std::size_t i = 0; i < n; ++i) {
    scaled[i] = {std::ldexp(input[i].x, sites.scale_exponent), std::ldexp(input[i].y, sites.scale_exponent)};
  }
  Box box{scaled[0].x, scaled[0].y, scaled[0].x, scaled[0].y};
  for (const Point2& p : scaled) {
    box = {std::min(box.min_x, p.x), std::min(box.min_y, p.y), std::max(box.max_x, p.x), std::max(box.max_y, p.y)};
  }
  REQUIRE(sites.bounds.min_x == box.min_x);
  REQUIRE(sites.bounds.min_y == box.min_y);
  REQUIRE(sites.bounds.max_x == box.max_x);
  REQUIRE(sites.bounds.max_y == box.max_y);
  const Quantiser quantiser(box);
  std::vector<std::uint64_t> codes(n);
  for (std::size_t i = 0; i < n; ++i) codes[i] = morton_code(quantiser.x(scaled[i].x), quantiser.y(scaled[i].y));
  std::vector<std::int32_t> order(n);
  std::iota(order.begin(), order.end(), 0);
  // By code, then (x, y) within a code: equal points side by side, in input order.
  std::stable_sort(order.begin(), order.end(), [&](std::int32_t a, std::int32_t b) {
    if (codes[a] != codes[b]) return codes[a] < codes[b];
    return scaled[a].x < scaled[b].x || (scaled[a].x == scaled[b].x && scaled[a].y < scaled[b].y);
  });
  std::vector<Point2> points;
  std::vector<std::int32_t> input_index, representative(n);
  std::size_t run_start = 0;
  for (std::size_t k = 0; k < n; ++k) {
    if (k == 0 || codes[order[k]] != codes[order[k - 1]]) run_start = points.size();
    const std::int32_t i = order[k];
    std::int32_t rep = i;
    for (std::size_t s = run_start; s < points.size(); ++s) {
      if (points[s] == scaled[i]) {
        rep = input_index[s];
        break;
      }
    }
    representative[i] = rep;
    if (rep == i) {
      points.push_back(scaled[i]);
      input_index.push_back(i);
    }
  }
  REQUIRE(sites.points.size() == points.size());
  CHECK(std::equal(points.begin(), points.end(), sites.points.begin()));
  CHECK(std::equal(input_index.begin(), input_index.end(), sites.input_index.begin()));
  CHECK(representative == sites.representative);
}

// The bucket tree as it was written sequentially: recursive split, cells filled recursively.
struct SequentialTree {
  std::vector<BucketTree::Node> nodes;
  std::vector<std::int32_t> cells;

  int capacity;

  explicit SequentialTree(const SiteSet& sites, const BucketTree& tree) : capacity(tree.capacity()) {
    const auto n = static_cast<std::int32_t>(sites.size());
    std::vector<std::uint64_t> codes(static_cast<std::size_t>(n));
    for (std::int32_t i = 0; i < n; ++i) {
      codes[i] = morton_code(tree.quantise_x(sites.points[i].x), tree.quantise_y(sites.points[i].y));
    }
    nodes.push_back({0, 0, 1u << BucketTree::quant_bits, -1, 0, n});
    split(0, codes);
    const int level = tree.grid_cells_per_side() == 1 ? 0 : std::countr_zero(static_cast<unsigned>(tree.grid_cells_per_side()));
    cells.assign(std::size_t{1} << (2 * level), -1);
    fill(0, level, tree.cell_shift());
  }
  void split(std::int32_t index, const std::vector<std::uint64_t>& codes) {
    const BucketTree::Node parent = nodes[index];
    if (parent.end - parent.begin <= capacity || parent.size == 1) return;
    const auto first = static_cast<std::int32_t>(nodes.size());
    nodes[index].first_child = first;
    nodes.resize(nodes.size() + 4);
    const std::uint32_t half = parent.size / 2;
    const int shift = std::countr_zero(half);
    std::int32_t lo = parent.begin;
    for (int q = 0; q < 4; ++q) {
      std::int32_t hi = lo;
      while (hi < parent.end && static_cast<int>((codes[hi] >> (2 * shift)) & 3u) <= q) ++hi;
      nodes[first + q] = {parent.x0 + ((q & 1) ? half : 0), parent.y0 + ((q & 2) ? half : 0), half, -1, lo, hi};
      lo = hi;
    }
    for (int q = 0; q < 4; ++q) split(first + q, codes);
  }
  void fill(std::int32_t index, int level, int shift) {
    const BucketTree::Node& node = nodes[index];
    if (node.first_child >= 0 && node.size > (1u << shift)) {
      for (int k = 0; k < 4; ++k) fill(node.first_child + k, level, shift);
      return;
    }
    const std::uint32_t i0 = node.x0 >> shift, j0 = node.y0 >> shift;
    const std::uint32_t side = std::max<std::uint32_t>(1, node.size >> shift);
    for (std::uint32_t j = j0; j < j0 + side; ++j) {
      for (std::uint32_t i = i0; i < i0 + side; ++i) cells[(std::size_t{j} << level) + i] = index;
    }
  }
};

bool same_nodes(const HostVector<BucketTree::Node>& a, const std::vector<BucketTree::Node>& b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](const auto& x, const auto& y) {
           return x.x0 == y.x0 && x.y0 == y.y0 && x.size == y.size && x.first_child == y.first_child &&
                  x.begin == y.begin && x.end == y.end;
         });
}

// Tasks 17 and 63 of 100 throw: the caller gets task 17's exception, whichever ran first.
void check_lowest_exception() {
  try {
    parallel_tasks(100, [](std::size_t i) {
      if (i == 17 || i == 63) throw std::runtime_error(std::to_string(i));
    });
    FAIL("no exception");
  } catch (const std::runtime_error& e) {
    CHECK(std::string(e.what()) == "17");
  }
}

}  // namespace

TEST_CASE("parallel tasks: every task once, the lowest task's exception, nested calls inline", "[parallel]") {
  for (std::size_t threads : thread_counts) {
    Threads use(threads);
    std::vector<std::atomic<int>> runs(1000);
    parallel_tasks(runs.size(), [&](std::size_t i) {
      runs[i]++;
      parallel_tasks(3, [&](std::size_t) { runs[i]++; });  // nested: on this thread
    });
    for (auto& r : runs) REQUIRE(r.load() == 4);
    check_lowest_exception();
    std::size_t covered = 0;
    parallel_chunks(1'000'003, [&](std::size_t, std::size_t begin, std::size_t end) {
      std::atomic_ref<std::size_t>(covered).fetch_add(end - begin);
    });
    CHECK(covered == 1'000'003);
  }
}

TEST_CASE("parallel tasks: a pass from another thread while one runs gets threads of its own",
          "[parallel]") {
  Threads use(4);
  std::atomic<bool> first_started{false}, second_done{false};
  std::atomic<int> outer_runs{0};
  // The first pass holds its threads until the second, started on another thread, has finished.
  std::thread first([&] {
    parallel_tasks(4, [&](std::size_t) {
      first_started = true;
      while (!second_done.load()) std::this_thread::yield();
      outer_runs++;
    });
  });
  while (!first_started.load()) std::this_thread::yield();
  {
    std::vector<std::atomic<int>> runs(64);
    std::mutex ids_mutex;
    std::set<std::thread::id> ids;
    parallel_tasks(runs.size(), [&](std::size_t i) {
      runs[i]++;
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
      std::lock_guard lock(ids_mutex);
      ids.insert(std::this_thread::get_id());
    });
    for (auto& r : runs) REQUIRE(r.load() == 1);
    CHECK(ids.size() > 1);
    check_lowest_exception();
    second_done = true;
  }
  first.join();
  CHECK(outer_runs.load() == 4);
}

TEST_CASE("prepare_sites: the sequential sort and merge, whatever the threads", "[parallel][input]") {
  // 600K sites make 8 top buckets of ~75K: the parallel path for large buckets and the
  // one-thread path both run; kuzmin and clusters are skewed, duplicates merges.
  for (const char* distribution : {"uniform", "kuzmin", "clusters", "duplicates", "grid"}) {
    const std::vector<Point2> points = generate_points(distribution, 600000, 21);
    for (std::size_t threads : thread_counts) {
      INFO(distribution << ", " << threads << " threads");
      Threads use(threads);
      check_against_sequential(points, prepare_sites(points));
    }
  }
}

TEST_CASE("prepare_sites: equal points in one long run across chunks keep the first", "[parallel][input]") {
  std::vector<Point2> points = generate_points("uniform", 400000, 4);
  for (std::size_t i = 100000; i < 300000; ++i) points[i] = {0.25, 0.75};  // one run of 200K
  points[150000] = {-0.0, 0.0};
  points[250000] = {0.0, -0.0};  // equal to the point before it
  for (std::size_t threads : thread_counts) {
    Threads use(threads);
    const SiteSet sites = prepare_sites(points);
    check_against_sequential(points, sites);
    CHECK(sites.representative[250000] == 150000);
    CHECK(sites.representative[299999] == 100000);
  }
}

TEST_CASE("prepare_sites: long runs of equal codes (x as a radix key, signed zeros, equal x) and a sampled split", "[parallel][input]") {
  // Far outliers make one quantum wide, so the centre's sites share codes in runs of thousands:
  // the runs are sorted by x as a radix key, then equal x by (y, input index). Signed zeros
  // must merge; equal x with different y must order by y. Most sites in a tiny cluster: the
  // top-level split follows the sample down many levels.
  std::mt19937_64 random(12);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::vector<Point2> points;
  points.push_back({-1e6, -1e6});
  points.push_back({1e6, 1e6});
  for (int i = 0; i < 300000; ++i) {
    const double x = unit(random), y = unit(random);
    switch (i % 7) {
      case 0: points.push_back({x, y}); break;
      case 1: points.push_back({std::ldexp(x, -20), std::ldexp(y, -20)}); break;  // finer than a quantum
      case 2: points.push_back({0.25, std::ldexp(y, -10)}); break;                 // equal x
      case 3: points.push_back({(i % 2) ? 0.0 : -0.0, (i % 3) ? -0.0 : 0.0}); break;  // one point
      case 4: points.push_back({std::ldexp(x, -30), 0.5}); break;
      case 5: points.push_back(points[points.size() / 2]); break;  // a duplicate of an earlier point
      default: points.push_back({std::round(x * 64) / 64, std::round(y * 64) / 64}); break;  // a lattice
    }
  }
  for (std::size_t threads : thread_counts) {
    INFO(threads << " threads");
    Threads use(threads);
    check_against_sequential(points, prepare_sites(points));
  }
}

TEST_CASE("bucket tree: the sequential split, whatever the threads (8- and 256-site buckets)", "[parallel][grid]") {
  for (const char* distribution : {"uniform", "kuzmin", "clusters", "grid", "line"}) {
    const std::vector<Point2> points = generate_points(distribution, 700000, 5);
    const SiteSet sites = prepare_sites(points);
    std::vector<BucketTree::Node> reference;
    for (std::size_t threads : thread_counts) {
      INFO(distribution << ", " << threads << " threads");
      Threads use(threads);
      const BucketTree tree(sites, threads == 2 ? BucketTree::coarse_capacity : BucketTree::bucket_capacity);
      const SequentialTree sequential(sites, tree);
      REQUIRE(same_nodes(tree.nodes(), sequential.nodes));
      const int side = tree.grid_cells_per_side();
      bool cells_equal = true;
      for (int j = 0; j < side; ++j) {
        for (int i = 0; i < side; ++i) cells_equal &= tree.cell_node(i, j) == sequential.cells[(std::size_t(j) * side) + i];
      }
      CHECK(cells_equal);
    }
  }
}

TEST_CASE("bucket tree: sites out of Morton order are refused", "[parallel][grid]") {
  const std::vector<Point2> points = generate_points("uniform", 300000, 6);
  SiteSet sites = prepare_sites(points);
  for (std::size_t k : {std::size_t{1}, std::size_t{123457}, sites.points.size() - 1}) {
    SiteSet broken = sites;
    std::swap(broken.points[k - 1], broken.points[k]);
    for (std::size_t threads : thread_counts) {
      Threads use(threads);
      try {
        const BucketTree tree(broken);
        FAIL("accepted unsorted sites");
      } catch (const Error& e) {
        CHECK(e.code() == ErrorCode::internal);
      }
    }
  }
}

TEST_CASE("bucket tree on demand: a bucket a search reaches over sites out of Morton order is refused", "[grid]") {
  const std::vector<Point2> points = generate_points("uniform", 20000, 6);
  const SiteSet sites = prepare_sites(points);
  SiteSet broken = sites;
  std::reverse(broken.points.begin(), broken.points.end());
  const BucketTree tree = BucketTree::on_demand(broken);
  ApexSearch search(broken, tree);
  try {
    (void)search.nearest_site(0);
    FAIL("searched unsorted sites");
  } catch (const Error& e) {
    CHECK(e.code() == ErrorCode::internal);
  }
}

TEST_CASE("allocate_full_triangulation: room for every triangle, shrinks in place", "[seam]") {
  for (std::size_t threads : thread_counts) {
    Threads use(threads);
    PartialTriangulation partial;
    const std::size_t sites = 300000, hull_sites = 17, full = 2 * sites - hull_sites - 2;
    allocate_full_triangulation(partial, sites, hull_sites);
    REQUIRE(partial.triangles.size() == full);
    REQUIRE(partial.neighbors.size() == full);
    // The ids are left unset (IdTriple): the backend writes every one it keeps.
    const Triangle* storage = partial.triangles.data();
    std::fill(partial.triangles.begin(), partial.triangles.end(), Triangle{4, 5, 6});
    partial.triangles.resize(full / 2);
    partial.triangles.push_back({1, 2, 3});  // what the seam stage appends stays where it is
    CHECK(partial.triangles.data() == storage);
    CHECK(partial.triangles[full / 2 - 1] == Triangle{4, 5, 6});
    CHECK(partial.triangles.back() == Triangle{1, 2, 3});
  }
}

TEST_CASE("hull, neighbours, audit and output remap: the same with any number of threads", "[parallel][seam]") {
  const std::vector<Point2> points = generate_points("uniform", 200000, 8);
  const SiteSet sites = prepare_sites(points);
  std::vector<std::int32_t> site_of(points.size());
  for (std::int32_t s = 0; s < sites.size(); ++s) site_of[sites.input_index[s]] = s;
  const test::OracleResult oracle = test::cgal_delaunay(points);
  std::vector<Triangle> triangles;
  for (const Triangle& t : oracle.triangles) triangles.push_back({site_of[t[0]], site_of[t[1]], site_of[t[2]]});
  const auto expected_neighbors = test::compute_neighbors(triangles);

  Threads one(1);
  const Hull reference_hull = convex_hull(sites);
  for (std::size_t threads : thread_counts) {
    INFO(threads << " threads");
    Threads use(threads);
    const Hull hull = convex_hull(sites);
    CHECK(hull.sites == reference_hull.sites);
    CHECK(std::equal(hull.predecessor.begin(), hull.predecessor.end(), reference_hull.predecessor.begin(),
                     reference_hull.predecessor.end()));

    PartialTriangulation partial;
    partial.triangles = triangles;
    partial.neighbors = derive_neighbors(partial.triangles);
    REQUIRE(partial.neighbors == expected_neighbors);
    CHECK(adjacency_is_trustworthy(partial, hull));

    // Two interior links swapped symmetrically: every link still has a partner that links
    // back, but across the wrong edges.
    PartialTriangulation swapped = partial;
    std::size_t t1 = 1000, t2 = 150000;
    while (swapped.neighbors[t1][0] == no_neighbor) ++t1;
    while (swapped.neighbors[t2][0] == no_neighbor) ++t2;
    const std::int32_t u1 = swapped.neighbors[t1][0], u2 = swapped.neighbors[t2][0];
    const auto relink = [&](std::size_t t, std::int32_t from, std::int32_t to) {
      for (auto& v : swapped.neighbors[t]) {
        if (v == from) v = to;
      }
    };
    relink(t1, u1, u2);
    relink(static_cast<std::size_t>(u2), static_cast<std::int32_t>(t2), static_cast<std::int32_t>(t1));
    relink(t2, u2, u1);
    relink(static_cast<std::size_t>(u1), static_cast<std::int32_t>(t1), static_cast<std::int32_t>(t2));
    CHECK_FALSE(adjacency_is_trustworthy(swapped, hull));

    // A seam: the triangles around a few sites left out; their edges are open on one side only.
    PartialTriangulation seam;
    for (const Triangle& t : triangles) {
      if (t[0] % 50000 != 7 && t[1] % 50000 != 7 && t[2] % 50000 != 7) seam.triangles.push_back(t);
    }
    seam.neighbors = derive_neighbors(seam.triangles);
    CHECK(adjacency_is_trustworthy(seam, hull));
    // The same edge claimed open from both sides is caught.
    for (std::size_t t = 0; t < seam.triangles.size(); ++t) {
      const std::int32_t u = seam.neighbors[t][1];
      if (u == no_neighbor) continue;
      seam.neighbors[t][1] = no_neighbor;
      for (auto& v : seam.neighbors[u]) {
        if (v == static_cast<std::int32_t>(t)) v = no_neighbor;
      }
      break;
    }
    CHECK_FALSE(adjacency_is_trustworthy(seam, hull));

    std::vector<Triangle> remapped = triangles;
    remap_to_input(remapped, sites);
    CHECK(test::compare_triangles(remapped, oracle.triangles).equal);
    CHECK(std::equal(remapped.begin(), remapped.end(), oracle.triangles.begin(), oracle.triangles.end()));
  }
}

TEST_CASE("seam stage: the same triangles, in the same order, over 8- and 256-site buckets and on demand", "[parallel][seam]") {
  for (const char* distribution : {"uniform", "kuzmin", "grid"}) {
    const std::vector<Point2> points = generate_points(distribution, 300000, 9);
    const SiteSet sites = prepare_sites(points);
    const Hull hull = convex_hull(sites);
    std::vector<std::int32_t> site_of(points.size());
    for (std::int32_t s = 0; s < sites.size(); ++s) site_of[sites.input_index[s]] = s;
    std::vector<Triangle> all;
    for (const Triangle& t : test::cgal_delaunay(points).triangles) all.push_back({site_of[t[0]], site_of[t[1]], site_of[t[2]]});
    // The sites of the widest triangles: the hull-hugging slivers a GPU leaves to the seam stage,
    // whose searches follow strips along the hull (the on-demand tree's tight boxes).
    std::vector<bool> widest(sites.points.size(), false);
    {
      std::vector<std::pair<double, std::size_t>> radius;
      for (std::size_t t = 0; t < all.size(); ++t) {
        const Point2 a = sites.points[all[t][0]], b = sites.points[all[t][1]], c = sites.points[all[t][2]];
        const double bx = b.x - a.x, by = b.y - a.y, cx = c.x - a.x, cy = c.y - a.y;
        const double d = 2 * (bx * cy - by * cx);
        const double ux = (cy * (bx * bx + by * by) - by * (cx * cx + cy * cy)) / d;
        const double uy = (bx * (cx * cx + cy * cy) - cx * (bx * bx + by * by)) / d;
        radius.push_back({-(ux * ux + uy * uy), t});
      }
      std::partial_sort(radius.begin(), radius.begin() + 40, radius.end());
      for (std::size_t k = 0; k < 40; ++k) {
        for (const std::int32_t v : all[radius[k].second]) widest[static_cast<std::size_t>(v)] = true;
      }
    }
    const std::size_t expected = 2 * sites.points.size() - hull.sites.size() - 2;
    const BucketTree fine_tree(sites);
    for (const bool along_hull : {false, true}) {
      INFO(distribution << (along_hull ? ", the widest triangles' sites open" : ", holes and two hull sites open"));
      PartialTriangulation partial;
      for (const Triangle& u : all) {
        // A few holes, and everything around two hull sites; or the widest triangles' sites.
        const bool open = along_hull ? widest[u[0]] || widest[u[1]] || widest[u[2]]
                                     : u[0] % 40000 == 3 || u[1] % 40000 == 3 || u[2] % 40000 == 3 ||
                                           std::find(u.begin(), u.end(), hull.sites[0]) != u.end() ||
                                           std::find(u.begin(), u.end(), hull.sites[hull.sites.size() / 2]) != u.end();
        if (!open) partial.triangles.push_back(u);
      }
      REQUIRE(partial.triangles.size() < all.size());
      const BucketTree seam_tree = BucketTree::for_seam(sites, expected - partial.triangles.size());
      REQUIRE(seam_tree.is_on_demand());
      PartialTriangulation fine = partial, coarse = partial, on_demand = partial;
      complete_seam(sites, hull, fine_tree, fine);
      complete_seam(sites, hull, BucketTree(sites, BucketTree::coarse_capacity), coarse);
      complete_seam(sites, hull, seam_tree, on_demand);
      CHECK(fine.triangles == coarse.triangles);
      CHECK(fine.neighbors == coarse.neighbors);
      CHECK(fine.triangles == on_demand.triangles);
      CHECK(fine.neighbors == on_demand.neighbors);
      // And the triangles are CGAL's.
      std::vector<Triangle> made = fine.triangles;
      remap_to_input(made, sites);
      std::vector<Triangle> oracle = all;
      remap_to_input(oracle, sites);
      CHECK(test::compare_triangles(made, oracle).equal);
      // The on-demand tree split only where the seam's searches went: its cost follows the seam.
      CHECK(seam_tree.nodes().size() * 20 < fine_tree.nodes().size());
    }
  }
}

TEST_CASE("host tuning: EXPANSE_HOST_THREADS read into Tuning::threads, invalid values ignored", "[parallel]") {
  const char* before = std::getenv("EXPANSE_HOST_THREADS");
  const std::string saved = before ? before : "";
  const auto threads_with = [](const char* value) {
    if (value) {
      setenv("EXPANSE_HOST_THREADS", value, 1);
    } else {
      unsetenv("EXPANSE_HOST_THREADS");
    }
    return host::tuning_from_environment().threads;
  };
  CHECK(threads_with("3") == 3);
  CHECK(threads_with(nullptr) == 0);
  CHECK(threads_with("0") == 0);
  CHECK(threads_with("-2") == 0);
  CHECK(threads_with("many") == 0);
  if (before) {
    setenv("EXPANSE_HOST_THREADS", saved.c_str(), 1);
  } else {
    unsetenv("EXPANSE_HOST_THREADS");
  }
}
