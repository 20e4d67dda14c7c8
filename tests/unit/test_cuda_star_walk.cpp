// The CUDA backend's per-site search and star walk (cuda_backend/device_geometry.cuh,
// star_walk.cuh), compiled for the CPU and run site by site: every machine tests the CUDA
// kernels' geometry against CGAL, GPU or not. (The CUDA compiler, memory and launch code are
// tested by tests/cuda on a device.)
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <random>
#include <set>
#include <string>

#include "expanse/generate.hpp"
#include "predicates/predicates.hpp"
#include "star_host.hpp"
#include "support/cgal_oracle.hpp"
#include "support/test_points.hpp"

using namespace expanse;
using namespace expanse::detail;

namespace {

std::array<std::int32_t, 3> canonical(Triangle t) {
  std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
  return t;
}

struct Family {
  std::string name;
  std::vector<Point2> (*make)(std::size_t, std::uint64_t);
  std::size_t n;
  /// The most the walk may leave to the seam stage, on the quantile (default) and the uniform
  /// grid. Nearly cocircular families off a lattice lean on the device's exact path: the
  /// certificate, and the incircle from exact coordinate differences (which decides them where
  /// the differences are exact; before it, the walk deferred nearly all of their sites). 1: no
  /// bound, where a family's structure defeats the walk (the test still checks what it decides).
  double max_deferred_quantile, max_deferred_uniform;
};

const char* name_of(cuda::StarSearch search) { return search == cuda::StarSearch::boxes ? "boxes" : "rings"; }

cuda::StarWorkTotals check_family(const Family& family, bool quantile, cuda::StarSearch search,
                                  bool two_phases = false, bool strips = false) {
  const std::vector<Point2> points = family.make(family.n, 5);
  const SiteSet sites = prepare_sites(points);
  const Hull hull = convex_hull(sites);
  REQUIRE(!hull.collinear);
  cuda::HostStarLayout layout(sites, hull, 2.0, quantile);
  layout.verify_inbox_walks(two_phases);
  layout.use_strips(strips);
  const cuda::StarWorkTotals totals = layout.walk_all(0, 1, search, two_phases);
  // A star taken whole from the inbox is the star the full walk makes.
  if (two_phases) CHECK(totals.inbox_walk_mismatches == 0);
  const std::vector<bool> deferred = layout.deferred_sites();

  std::set<std::array<std::int32_t, 3>> expected;
  for (const Triangle& t : test::cgal_delaunay(points).triangles) expected.insert(canonical(t));

  std::set<std::array<std::int32_t, 3>> emitted;
  for (Triangle t : layout.owned_triangles_in_site_ids()) {
    for (std::int32_t& v : t) v = sites.input_index[v];
    const auto key = canonical(t);
    INFO(family.name << (quantile ? " (quantile grid, " : " (uniform grid, ") << name_of(search) << "): triangle " << key[0] << ' '
                     << key[1] << ' ' << key[2]);
    REQUIRE(expected.count(key) == 1);   // exact: a Delaunay triangle of CGAL's, CCW
    REQUIRE(emitted.insert(key).second);  // emitted once
  }
  // Every triangle none of whose vertices deferred was made (its owner walked it).
  std::vector<std::int32_t> site_of_input(points.size(), -1);
  for (std::size_t s = 0; s < sites.points.size(); ++s) site_of_input[sites.input_index[s]] = static_cast<std::int32_t>(s);
  std::size_t decidable = 0;
  for (const auto& t : expected) {
    if (deferred[site_of_input[t[0]]] || deferred[site_of_input[t[1]]] || deferred[site_of_input[t[2]]]) continue;
    ++decidable;
    INFO(family.name << ": missing triangle " << t[0] << ' ' << t[1] << ' ' << t[2]);
    REQUIRE(emitted.count(t) == 1);
  }
  INFO(family.name << ": " << totals.deferred << " of " << totals.sites << " sites deferred (" << totals.deferred_undecided
                   << " undecided or over budget, " << totals.deferred_full_row << " full row, " << totals.deferred_no_apex
                   << " no apex; max work " << totals.max_work << ")");
  const double bound = quantile ? family.max_deferred_quantile : family.max_deferred_uniform;
  CHECK(static_cast<double>(totals.deferred) <= bound * static_cast<double>(totals.sites));
  if (bound < 1.0) CHECK(decidable > 0);
  return totals;
}

}  // namespace

TEST_CASE("CUDA star walk on the CPU: exact against CGAL on adversarial families", "[cuda][star]") {
  namespace p = test::points;
  const std::vector<Family> families = {
      {"uniform", p::uniform, 20000, 0.001, 0.001},
      {"gaussian", p::gaussian, 20000, 0.001, 0.001},
      // The uniform grid piles kuzmin's core into a few cells and runs out of budget: the
      // quantile grid is the default for this reason.
      {"kuzmin", p::kuzmin, 20000, 0.01, 1.0},
      // A box 16 times taller than wide: quantile cells keep as many columns as rows.
      {"kuzmin, stretched",
       [](std::size_t n, std::uint64_t seed) {
         std::vector<Point2> points = p::kuzmin(n, seed);
         for (Point2& q : points) q.y *= 16.0;
         return points;
       },
       20000, 0.01, 1.0},
      {"clusters", p::clusters, 20000, 0.002, 0.002},
      {"grid", p::grid, 10000, 0.001, 0.001},
      {"rotated_grid_exact", p::rotated_grid_exact, 4000, 0.002, 0.002},
      {"rotated_grid_float", p::rotated_grid_float, 4000, 0.05, 0.05},
      // Nearly cocircular, every coordinate difference exact: decided by the exact path
      // (incircle_exact_differences); only a star too large for its row defers (the partial
      // last row's fan).
      {"decimal_grid", p::decimal_grid, 4000, 0.001, 0.001},
      // The centre, in every triangle, has a star too large for its row: nothing to compare.
      {"lattice_circle", p::lattice_circle, 2000, 1.0, 1.0},
      {"duplicates", p::duplicates, 6000, 0.001, 0.001},
      {"offset", p::offset, 3000, 0.01, 0.5},
      {"thin_circle", p::thin_circle, 2000, 1.0, 1.0},  // the ring search runs out of budget
      {"square_boundary", p::square_boundary, 2000, 0.001, 0.001},
      {"two_lines", p::two_lines, 2000, 0.001, 0.001},
      {"cross", p::cross, 2000, 0.001, 0.001},
  };
  for (const auto search : {cuda::StarSearch::boxes, cuda::StarSearch::rings}) {
    for (const bool quantile : {true, false}) {
      for (const Family& family : families) {
        DYNAMIC_SECTION(family.name << (quantile ? " quantile " : " uniform ") << name_of(search)) {
          const cuda::StarWorkTotals alone = check_family(family, quantile, search);
          if (search == cuda::StarSearch::boxes) {
            // Two phases (StarInbox): the odd sites' walks start from and step through what the
            // even sites posted, and must make the same stars, searching for about one triangle
            // in four. (Deferrals may differ either way: a walk that starts at another
            // neighbour runs other searches, and check_family bounds them.)
            const cuda::StarWorkTotals phased = check_family(family, quantile, search, true);
            if (alone.deferred == 0) CHECK(phased.predicates < alone.predicates);
            if (alone.deferred == 0) CHECK(phased.from_inbox > 0);  // stars taken whole from inboxes
            // The boundary strips (the edge's walks and the second pass) change which sites a
            // search tests, never the star (check_family compares it with CGAL's).
            check_family(family, quantile, search, false, true);
          }
        }
      }
    }
  }
}

namespace {

/// Where site o's StarView (the emit's reads) differs from star_at and star_find: entries at
/// t in [-1, degree + 1], the position of each neighbour and of a site not in the star, and the
/// owned bits counted from star_at.
int star_view_mismatches(const int* rows, std::uint32_t info, int o) {
  const cuda::StarView view(rows, info, o);
  const int deg = cuda::star_degree(info);
  int bad = 0;
  std::uint32_t owned = 0;
  for (int t = -1; t <= deg + 1; ++t) bad += view.at(t) != cuda::star_at(rows, info, o, t);
  for (int t = 0; t < deg; ++t) {
    const int u = cuda::star_at(rows, info, o, t);
    bad += view.find(u) != cuda::star_find(rows, info, o, u);
  }
  bad += view.find(-5) != -1;
  for (int t = 0; t < (cuda::star_closed(info) ? deg : deg - 1); ++t) {
    const int a = cuda::star_at(rows, info, o, t), b = cuda::star_at(rows, info, o, t + 1);
    owned |= static_cast<std::uint32_t>(o < a && o < b) << t;
  }
  bad += view.owned_mask() != owned;
  return bad;
}

}  // namespace

TEST_CASE("CUDA emit: StarView reads every star as star_at and star_find read it", "[cuda][star]") {
  namespace p = test::points;
  SECTION("the walks' stars: closed ones in their row's first sector, hull stars wrapping") {
    for (const auto make : {p::uniform, p::kuzmin, p::grid}) {
      const std::vector<Point2> points = make(5000, 3);
      const SiteSet sites = prepare_sites(points);
      cuda::HostStarLayout layout(sites, convex_hull(sites), 2.0, true);
      layout.walk_all(0, 1, cuda::StarSearch::boxes, false);
      int heads = 0, rows = 0, bad = 0;
      for (std::size_t i = 0; i < layout.site_count(); ++i) {
        const std::uint32_t info = layout.star_info_of(i);
        if (cuda::star_deferred(info)) continue;
        (cuda::StarView(layout.star_rows(), info, static_cast<int>(i)).head ? heads : rows) += 1;
        bad += star_view_mismatches(layout.star_rows(), info, static_cast<int>(i));
      }
      CHECK(bad == 0);
      CHECK(heads > 0);  // both of StarView's paths are taken
      CHECK(rows > 0);
    }
  }
  SECTION("any row: every start, degrees 1 to kStar, open and closed") {
    std::mt19937 rng(7);
    std::vector<int> rows(4 * cuda::kStar);
    int bad = 0;
    for (int start = 0; start < cuda::kStar; ++start)
      for (int deg = 1; deg <= cuda::kStar; ++deg)
        for (const bool closed : {false, true}) {
          for (int& v : rows) v = static_cast<int>(rng() % 16);  // repeats: find() takes the first
          const int o = static_cast<int>(rng() % 4);
          const std::uint32_t info = static_cast<std::uint32_t>(deg) | (static_cast<std::uint32_t>(start) << 8) |
                                     (closed ? cuda::kClosedBit : 0u);
          bad += star_view_mismatches(rows.data(), info, o);
        }
    CHECK(bad == 0);
  }
}

TEST_CASE("CUDA star walk on the CPU: the first pass's light walk makes the full walk's star, or hands on",
          "[cuda][star]") {
  // The first pass walks without the exact path and without cutting rows to the search's region
  // (walk_star_boxes' FirstPass). A site it finishes must have the full walk's star; one it
  // cannot finish (a candidate the filters cannot decide, or the budget spent) goes to the
  // second pass; any other deferral must be the full walk's too.
  namespace p = test::points;
  const std::vector<Family> families = {
      {"uniform", p::uniform, 20000, 0, 0},           {"kuzmin", p::kuzmin, 20000, 0, 0},
      {"rotated_grid_float", p::rotated_grid_float, 4000, 0, 0}, {"lattice_circle", p::lattice_circle, 2000, 0, 0},
      {"thin_circle", p::thin_circle, 2000, 0, 0},   {"grid", p::grid, 10000, 0, 0},
      {"square_boundary", p::square_boundary, 2000, 0, 0},
  };
  for (const Family& family : families) {
    for (const unsigned budget : {1u << 10, cuda::default_budget(cuda::StarSearch::boxes)}) {
      DYNAMIC_SECTION(family.name << ", budget " << budget) {
        const SiteSet sites = prepare_sites(family.make(family.n, 5));
        const cuda::HostStarLayout layout(sites, convex_hull(sites), 2.0, true);
        const unsigned full_budget = cuda::default_budget(cuda::StarSearch::boxes);
        std::size_t handed_on = 0, finished = 0;
        for (int i = 0; i < static_cast<int>(sites.points.size()); ++i) {
          std::array<int, cuda::kStar> full_row{}, light_row{};
          full_row.fill(-1);
          light_row.fill(-1);
          const cuda::StarWalk full = layout.walk_site(i, full_row.data(), full_budget, false);
          const cuda::StarWalk light = layout.walk_site(i, light_row.data(), budget, true);
          INFO(family.name << ": site " << i);
          REQUIRE_FALSE(full.handed_on);
          if (light.handed_on || light.work > budget) {
            REQUIRE_FALSE(light.ok);
            handed_on += light.handed_on;
            continue;
          }
          REQUIRE(light.ok == full.ok);
          REQUIRE(light.reason == full.reason);
          if (full.ok) {
            ++finished;
            REQUIRE(light.ccw == full.ccw);
            REQUIRE(light.cw == full.cw);
            REQUIRE(light.closed == full.closed);
            REQUIRE(light_row == full_row);
          }
        }
        CHECK(finished + handed_on > 0);  // the comparison, or the hand-on, is exercised
        if (family.name == "uniform" || family.name == "kuzmin") CHECK(finished > sites.points.size() / 2);
        // Nearly cocircular sites off a lattice are where the filters fail: the path is exercised.
        if (family.name == "lattice_circle" || family.name == "rotated_grid_float") CHECK(handed_on > 0);
        if (family.name == "grid") CHECK(handed_on == 0);  // decided in the scan (ExactLattice)
      }
    }
  }
}

TEST_CASE("CUDA star walk on the CPU: uniform sites near the hull neither overflow nor run away", "[cuda][star]") {
  // Sites on the flat hull sides of a uniform set fan out to many long, nearly flat triangles.
  // With 16-neighbour star rows one of these 20000 sites deferred (full row), which sends the
  // whole pipeline through the seam stage; and a search must stay local rather than scan the
  // grid. Work counts, not times.
  const std::vector<Point2> points = test::points::uniform(20000, 9);
  const SiteSet sites = prepare_sites(points);
  const Hull hull = convex_hull(sites);
  for (const auto search : {cuda::StarSearch::boxes, cuda::StarSearch::rings}) for (const bool quantile : {true, false}) {
    cuda::HostStarLayout layout(sites, hull, 2.0, quantile);
    const cuda::StarWorkTotals totals = layout.walk_all(0, 1, search);
    INFO(name_of(search) << ", " << (quantile ? "quantile" : "uniform") << " grid: max work " << totals.max_work << ", mean "
                                             << totals.work / totals.sites << "; deferred: " << totals.deferred_undecided
                                             << " undecided, " << totals.deferred_full_row << " full row, "
                                             << totals.deferred_no_apex << " no apex");
    // Work units: rings count the cells they visit (not those they cull) and their sites; box
    // scans count row segments (cut to the region, often to nothing) and sites. The costliest
    // site here is a hull-hugging one whose thin, tall regions span some 60 rows per search.
    CHECK(totals.max_work < (search == cuda::StarSearch::rings ? 2000u : 8000u));
    CHECK(totals.deferred == 0);
    // The per-site figures the work count splits by cell: they add up to the totals, and each
    // site's cell is its own (its k sites each add 1/k: a whole number of occupied cells).
    std::uint64_t work = 0, most = 0;
    double cells = 0.0;
    for (std::size_t i = 0; i < layout.site_count(); ++i) {
      work += layout.site_work(i);
      most = std::max<std::uint64_t>(most, layout.site_work(i));
      REQUIRE(layout.cell_occupancy(i) >= 1);
      cells += 1.0 / layout.cell_occupancy(i);
    }
    CHECK(work == totals.work);
    CHECK(most == totals.max_work);
    CHECK(std::abs(cells - std::round(cells)) < 1e-6);
    CHECK(std::round(cells) <= static_cast<double>(sites.points.size()));
  }
}

namespace {

/// The sites whose stars two walks of the same layout's sites left different (info word or row).
int differing_stars(const cuda::HostStarLayout& a, const cuda::HostStarLayout& b) {
  int differing = 0;
  for (std::size_t i = 0; i < a.site_count(); ++i) {
    const std::uint32_t info = a.star_info_of(i);
    bool same = b.star_info_of(i) == info;
    for (int t = 0; same && t < cuda::star_degree(info); ++t)
      same = cuda::star_at(a.star_rows(), info, static_cast<int>(i), t) ==
             cuda::star_at(b.star_rows(), info, static_cast<int>(i), t);
    differing += !same;
  }
  return differing;
}

}  // namespace

TEST_CASE("CUDA star walk on the CPU: boundary strips make the box scans' stars for far less hull-hugging work",
          "[cuda][star]") {
  // A uniform square's hull-hugging sites: nearly collinear runs along a side leave circles whose
  // region is a sliver along the whole side. Box scans visit every row of it; the strip (the
  // side's sites by inward coordinate) only those up to the region's inner bound.
  const std::vector<Point2> points = test::points::uniform(100000, 13);
  const SiteSet sites = prepare_sites(points);
  const Hull hull = convex_hull(sites);
  for (const bool quantile : {true, false}) {
    cuda::HostStarLayout boxes(sites, hull, 2.0, quantile), strips(sites, hull, 2.0, quantile);
    // The kernels take strips on equal cells only; on quantile cells the outer columns' tall
    // boxes are scanned across (TailColumns, tested below), which the strips are compared without.
    boxes.use_tail_columns(false);
    strips.use_tail_columns(false);
    strips.use_strips(true);
    const cuda::StarWorkTotals by_boxes = boxes.walk_all(0, 2), by_strips = strips.walk_all(0, 2);
    INFO((quantile ? "quantile" : "uniform") << " grid: max work " << by_boxes.max_work << " -> " << by_strips.max_work
                                             << ", total " << by_boxes.work << " -> " << by_strips.work);
    REQUIRE(by_boxes.deferred == 0);
    CHECK(by_strips.deferred == 0);
    CHECK(differing_stars(boxes, strips) == 0);
    CHECK(by_strips.work < by_boxes.work);
    // The costliest site is a hull-hugging one; on equal cells its long edges along the hull also
    // start with the cells along them (kLongEdgeCells).
    CHECK((quantile ? 1 : 2) * by_strips.max_work < by_boxes.max_work);
  }
}

TEST_CASE("CUDA star walk on the CPU: tall boxes in the outer columns scanned across make the same stars for less work",
          "[cuda][star]") {
  // Kuzmin's x-tails lie in wide columns that its dense centre cuts into thin rows: their boxes
  // run many rows tall and a few columns wide, a row segment a row unless scanned a column at a
  // time (TailColumns). Its y-tails' boxes are wide and short and take no copy.
  const std::vector<Point2> points = test::points::kuzmin(200000, 17);
  const SiteSet sites = prepare_sites(points);
  const Hull hull = convex_hull(sites);
  cuda::HostStarLayout rows(sites, hull, 2.0, true), across(sites, hull, 2.0, true);
  rows.use_tail_columns(false);
  for (const bool phases : {false, true}) {
    const cuda::StarWorkTotals by_rows = rows.walk_all(0, 2, cuda::StarSearch::boxes, phases);
    const cuda::StarWorkTotals by_columns = across.walk_all(0, 2, cuda::StarSearch::boxes, phases);
    INFO((phases ? "two phases" : "one phase") << ": work " << by_rows.work << " -> " << by_columns.work
                                               << ", lock-step " << by_rows.lockstep_work_32 << " -> "
                                               << by_columns.lockstep_work_32);
    REQUIRE(by_rows.deferred == by_columns.deferred);
    CHECK(differing_stars(rows, across) == 0);
    CHECK(by_columns.work < by_rows.work);
    CHECK(by_columns.lockstep_work_32 < by_rows.lockstep_work_32);
  }
}

TEST_CASE("CUDA star phases: blocks launched from both ends of the order run every block once", "[cuda][star]") {
  for (const int blocks : {1, 2, 3, 4, 5, 64, 65, 65537}) {
    std::vector<int> runs(blocks, 0);
    for (int b = 0; b < blocks; ++b) {
      const int block = cuda::ends_first_block(b, blocks);
      REQUIRE(block >= 0);
      REQUIRE(block < blocks);
      ++runs[block];
    }
    CHECK(std::all_of(runs.begin(), runs.end(), [](int r) { return r == 1; }));
    // Both ends first: the first two slots run the first and the last block.
    CHECK(cuda::ends_first_block(0, blocks) == 0);
    if (blocks > 1) CHECK(cuda::ends_first_block(1, blocks) == blocks - 1);
  }
}

TEST_CASE("CUDA box scans: a row cut to the search's region keeps every site of the region", "[cuda][star]") {
  // clip_row prunes rows with floating-point margins; a site it wrongly cut away could be a
  // better apex the search never sees. Random edges, candidates and sites, on a uniform and a
  // quantile grid of 64 x 64 cells: every site strictly left of a->b (exact orientation) and
  // inside the disc holding the candidate's region must lie in its row's cut segment.
  std::mt19937_64 random(17);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  constexpr int cells = 64;
  std::vector<double> bounds_x(cells + 1), bounds_y(cells + 1);
  for (int j = 0; j <= cells; ++j) {  // uneven columns and rows, as quantiles of a cluster give
    const double t = double(j) / cells;
    bounds_x[j] = t * t;
    bounds_y[j] = std::sqrt(t);
  }
  for (const bool quantile : {false, true}) {
    cuda::GridView g{};
    g.min_x = g.min_y = 0.0;
    g.max_x = g.max_y = 1.0;
    g.gx = g.gy = cells;
    g.inv_w = g.inv_h = cells;
    g.cell_w = g.cell_h = 1.0 / cells;
    if (quantile) {
      g.xb = bounds_x.data();
      g.yb = bounds_y.data();
    }
    std::size_t checked = 0, missed = 0;
    for (int trial = 0; trial < 2000; ++trial) {
      // Short edges, like a star's, and long ones, like a hull-hugging site's.
      const double2 a = make_double2(unit(random), unit(random));
      const double scale = trial % 2 ? 0.02 : 0.8;
      const double2 b = make_double2(std::clamp(a.x + scale * (unit(random) - 0.5), 0.0, 1.0),
                                     std::clamp(a.y + scale * (unit(random) - 0.5), 0.0, 1.0));
      const double2 c = make_double2(unit(random), unit(random));
      if (orient2d({a.x, a.y}, {b.x, b.y}, {c.x, c.y}) <= 0) continue;
      cuda::CircleRegion region;
      if (!cuda::circle_region(a, b, c, &region)) continue;
      cuda::SearchBounds bounds;
      bounds.apex = true;
      bounds.a = a;
      bounds.b = b;
      bounds.disc = trial % 3 != 0;  // also the half-plane alone, as before a first candidate
      bounds.ox = region.ox;
      bounds.oy = region.oy;
      bounds.reach = region.reach;
      for (int k = 0; k < 200; ++k) {
        // Sites near the edge's line and near the circle, where the margins matter.
        const double s = unit(random);
        double px = a.x + s * (b.x - a.x) + 1e-9 * (unit(random) - 0.5);
        double py = a.y + s * (b.y - a.y) + 1e-9 * (unit(random) - 0.5);
        if (k % 2) {
          const double angle = 6.283185307179586 * unit(random);
          px = region.ox + region.reach * std::cos(angle) * (1.0 - 1e-12);
          py = region.oy + region.reach * std::sin(angle) * (1.0 - 1e-12);
        }
        if (!(px >= 0.0 && px <= 1.0 && py >= 0.0 && py <= 1.0)) continue;
        if (orient2d({a.x, a.y}, {b.x, b.y}, {px, py}) <= 0) continue;
        const long double dx = (long double)px - region.ox, dy = (long double)py - region.oy;
        if (bounds.disc && dx * dx + dy * dy > (long double)region.reach * region.reach) continue;
        const int x = g.cell_x(px), y = g.cell_y(py);
        int x0 = 0, x1 = cells - 1;
        cuda::clip_row(g, y, bounds, &x0, &x1);
        ++checked;
        missed += !(x0 <= x && x <= x1);
      }
    }
    INFO((quantile ? "quantile" : "uniform") << " grid: " << checked << " sites checked");
    CHECK(checked > 50000);
    CHECK(missed == 0);
  }
}

TEST_CASE("CUDA star walk on the CPU: kuzmin's tails weighed make Delaunay stars for less work", "[cuda][star]") {
  // Kuzmin's Cauchy tails crowd the quantile cells along their diagonals; weighed tails give
  // them more columns and rows (quantile_tails).
  const std::vector<Point2> points = test::points::kuzmin(100000, 7);
  const SiteSet sites = prepare_sites(points);
  const Hull hull = convex_hull(sites);
  cuda::Tuning plain_quantiles;
  plain_quantiles.tails = parse_tail_weighing("0");
  cuda::HostStarLayout plain(sites, hull, 2.0, true, plain_quantiles);
  cuda::HostStarLayout weighed(sites, hull, 2.0, true);
  const cuda::StarWorkTotals by_plain = plain.walk_all(0, 2), by_weighed = weighed.walk_all(0, 2);
  INFO("work " << by_plain.work << " -> " << by_weighed.work << ", sites past 2^11 units " << by_plain.sites_over_pow2[0]
               << " -> " << by_weighed.sites_over_pow2[0] << ", deferred " << by_plain.deferred << " -> "
               << by_weighed.deferred);
  std::set<std::array<std::int32_t, 3>> expected;
  for (const Triangle& t : test::cgal_delaunay(points).triangles) expected.insert(canonical(t));
  std::size_t wrong = 0;
  for (Triangle t : weighed.owned_triangles_in_site_ids()) {
    for (std::int32_t& v : t) v = sites.input_index[v];
    wrong += expected.count(canonical(t)) != 1;
  }
  CHECK(wrong == 0);
  CHECK(by_weighed.deferred <= by_plain.deferred);
  CHECK(by_weighed.work < by_plain.work);
  CHECK(3 * by_weighed.sites_over_pow2[0] < 2 * by_plain.sites_over_pow2[0]);  // 154 -> 72
}

TEST_CASE("CUDA quantile grid: the guided cell lookup is the full binary search", "[cuda][grid]") {
  // Boundaries as clusters and heavy tails give them: most of the columns in a small part of the
  // axis (a power law at one end; Cauchy quantiles, kuzmin's marginals, spanning 10^12; the
  // paper's two gaussian clusters, their median between them), runs of equal boundaries
  // (duplicated coordinates), the median column of zero width, and values in, on, between and
  // outside them, subnormally close to the centre among them; axes near 0, negative, and narrow
  // far from 0 (where an interval is a few thousand ulps wide).
  std::mt19937_64 random(23);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> normal(0.0, 1.0);
  enum class Shape { power, cauchy, two_gaussians };
  struct Axis {
    double lo, hi;
    Shape shape;
  };
  const std::vector<Axis> axes = {{1.0, 4.0, Shape::power},
                                  {-3.0, -1.0, Shape::power},
                                  {0.5, 0.5 + std::ldexp(1.0, -30), Shape::power},
                                  {-1e12, 1e12, Shape::cauchy},
                                  {-0.2, 1.2, Shape::two_gaussians}};
  std::vector<double> mixture(1 << 18);
  for (std::size_t i = 0; i < mixture.size(); ++i)
    mixture[i] = std::clamp((i % 2 ? 0.3 : 0.7) + 0.08 * normal(random), -0.2, 1.2);
  std::sort(mixture.begin(), mixture.end());
  for (const Axis& axis : axes) {
    for (const int cells : {8, 9, 64, 1000, 2896}) {
      const double lo = axis.lo, hi = axis.hi, extent = hi - lo;
      auto quantile = [&](double t) {
        switch (axis.shape) {
          case Shape::power: return lo + extent * t * t * t * t;
          case Shape::cauchy: return std::clamp(std::tan(M_PI * (t - 0.5)), lo, hi);
          case Shape::two_gaussians: return mixture[std::min(mixture.size() - 1, std::size_t(t * mixture.size()))];
        }
        return lo;
      };
      std::vector<double> bounds(cells + 1);
      for (int j = 1; j < cells; ++j) bounds[j] = quantile(double(j) / cells);
      for (int j = 2; j + 1 < cells; j += 7) bounds[j] = bounds[j - 1];  // equal boundaries
      if (cells == 9) bounds[cells / 2 + 1] = bounds[cells / 2 - 1] = bounds[cells / 2];  // no central width
      REQUIRE(cuda::quantile_guided(cells));
      // Both keys must be exact; the one chosen must also narrow.
      std::vector<int> logarithmic_table, even_table, table;
      const QuantileGuideKey logarithmic = plan_logarithmic_quantile_guide(bounds.data() + 1, cells, lo, hi);
      const QuantileGuideKey even = plan_even_quantile_guide(lo, hi, cells);
      fill_quantile_guide(bounds.data() + 1, cells, logarithmic, logarithmic_table);
      fill_quantile_guide(bounds.data() + 1, cells, even, even_table);
      const QuantileGuideKey chosen = build_quantile_guide(bounds.data() + 1, cells, lo, hi, table);
      for (const auto& t : {logarithmic_table, even_table, table}) REQUIRE(int(t.size()) <= quantile_guide_capacity(cells));
      const std::array<cuda::QuantileGuide, 3> guides = {cuda::QuantileGuide{logarithmic_table.data(), logarithmic},
                                                         cuda::QuantileGuide{even_table.data(), even},
                                                         cuda::QuantileGuide{table.data(), chosen}};
      const cuda::QuantileGuide& guide = guides[2];
      const double centre = guide.key.centre;
      std::vector<double> values = {lo,   hi,   std::nextafter(lo, -HUGE_VAL), std::nextafter(hi, HUGE_VAL), -1e300, 1e300,
                                    0.0, centre, centre + 1e-310,             centre - 1e-310};
      for (int j = 1; j < cells; ++j)
        values.insert(values.end(), {bounds[j], std::nextafter(bounds[j], -HUGE_VAL), std::nextafter(bounds[j], HUGE_VAL)});
      for (int trial = 0; trial < 20000; ++trial) {
        const double t = 1.2 * unit(random) - 0.1;  // beyond the axis too
        values.push_back(t < 0.0 || t > 1.0 ? lo + extent * t : quantile(t));
      }
      std::size_t mismatches = 0, steps = 0;
      std::array<int, 3> previous{};
      std::sort(values.begin(), values.end());
      for (const double v : values) {
        const int plain = cuda::GridView::upper_index(bounds.data(), v, 0, cells - 1);
        for (std::size_t which = 0; which < guides.size(); ++which) {
          const int guided = cuda::GridView::quantile_index(bounds.data(), cells, guides[which], v);
          mismatches += plain != guided;
          if (guided < previous[which]) ++mismatches;  // monotone
          previous[which] = guided;
        }
        int narrow_lo = 0, narrow_hi = 0;
        guide.narrow(v, &narrow_lo, &narrow_hi);
        steps += narrow_hi - narrow_lo;
      }
      INFO("axis [" << lo << ", " << hi << "], " << cells << " columns, " << values.size() << " values, the "
                    << (chosen.logarithmic ? "logarithmic" : "even") << " key chosen, "
                    << double(steps) / double(values.size()) << " columns left to search on average");
      CHECK(mismatches == 0);
      // The guide narrows (a table that left the whole axis would pass the check above) for the
      // shapes inputs have: values placed as the sites are leave a few columns to search. (A
      // power law at one end of the axis, far from its median, is left to the even key's
      // bins and may leave more.)
      if (cells >= 64 && axis.shape != Shape::power) CHECK(double(steps) / double(values.size()) < 4.0);
    }
  }
}

TEST_CASE("CUDA box scans: a box of quantile cells holds a region by its boundaries exactly when by the look-ups",
          "[cuda][grid]") {
  // quantile_box_holds (the test that ends most searches on quantile cells) against what it
  // replaces, box_inside(cells_of(region), box): boxes at and away from the grid's sides, empty
  // ones, regions whose bounds fall on, beside and between boundaries (equal ones among them),
  // beyond the axis, and NaN (where the boundaries may only say no more often).
  std::mt19937_64 random(29);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const int gx = 37, gy = 23;
  auto axis = [&](int cells, double scale) {
    std::vector<double> bounds(cells + 1, 0.0);  // [0] and [cells] never read, as on the device
    for (int j = 1; j < cells; ++j) bounds[j] = scale * std::tan(M_PI * (double(j) / cells - 0.5));
    for (int j = 3; j + 1 < cells; j += 5) bounds[j] = bounds[j - 1];
    return bounds;
  };
  const std::vector<double> xb = axis(gx, 1.0), yb = axis(gy, 1e-6);
  cuda::GridView g{};
  g.gx = gx;
  g.gy = gy;
  g.xb = xb.data();
  g.yb = yb.data();
  g.min_x = -1e3;
  g.max_x = 1e3;
  g.min_y = -1e-3;
  g.max_y = 1e-3;
  auto value = [&](const std::vector<double>& bounds, int cells, double scale) {
    const double pick = unit(random);
    const int j = 1 + static_cast<int>(unit(random) * (cells - 1)) % (cells - 1);
    if (pick < 0.3) return bounds[j];
    if (pick < 0.45) return std::nextafter(bounds[j], -HUGE_VAL);
    if (pick < 0.6) return std::nextafter(bounds[j], HUGE_VAL);
    if (pick < 0.62) return std::numeric_limits<double>::quiet_NaN();
    return scale * std::tan(M_PI * (1.1 * unit(random) - 0.55));
  };
  std::size_t held = 0, mismatches = 0;
  for (int trial = 0; trial < 200000; ++trial) {
    auto side = [&](int cells) {
      const int a = static_cast<int>(unit(random) * cells), b = static_cast<int>(unit(random) * cells);
      const double pick = unit(random);
      if (pick < 0.1) return std::pair{0, std::max(a, b)};
      if (pick < 0.2) return std::pair{std::min(a, b), cells - 1};
      if (pick < 0.25) return std::pair{std::max(a, b), std::min(a, b) - 1};  // empty
      return std::pair{std::min(a, b), std::max(a, b)};
    };
    const auto [x0, x1] = side(gx);
    const auto [y0, y1] = side(gy);
    const cuda::CellBox box{x0, y0, x1, y1};
    double x_lo = value(xb, gx, 1.0), x_hi = value(xb, gx, 1.0);
    double y_lo = value(yb, gy, 1e-6), y_hi = value(yb, gy, 1e-6);
    if (x_lo > x_hi) std::swap(x_lo, x_hi);
    if (y_lo > y_hi) std::swap(y_lo, y_hi);
    const bool by_bounds = cuda::quantile_box_holds(g, box, x_lo, y_lo, x_hi, y_hi);
    const bool by_lookups = cuda::box_inside(cuda::cells_of(g, x_lo, y_lo, x_hi, y_hi), box);
    const bool nan = std::isnan(x_lo) || std::isnan(x_hi) || std::isnan(y_lo) || std::isnan(y_hi);
    held += by_bounds;
    mismatches += nan ? (by_bounds && !by_lookups) : by_bounds != by_lookups;
  }
  INFO(held << " of 200000 regions held");
  CHECK(mismatches == 0);
  CHECK(held > 1000);  // the test meets both answers
}

TEST_CASE("CUDA quantile cells: as many columns as rows, whatever the box, no more cells than uniform ones",
          "[cuda][grid]") {
  for (const double aspect : {1.0, 0.076, 13.0, 1e-3}) {
    const Box box{-1.0, 2.0, -1.0 + aspect, 3.0};
    for (const std::size_t n : {std::size_t{3}, std::size_t{1000}, std::size_t{1} << 24}) {
      const cuda::GridShape uniform = cuda::make_grid_shape(box, n, 2.0);
      const cuda::GridShape q = cuda::quantile_shape(uniform, box);
      INFO("aspect " << aspect << ", n " << n << ": uniform " << uniform.gx << " x " << uniform.gy);
      CHECK(q.gx == q.gy);
      CHECK(q.gx >= 1);
      CHECK(static_cast<std::size_t>(q.gx) * q.gy <= static_cast<std::size_t>(uniform.gx) * uniform.gy);
      CHECK(static_cast<double>(q.gx + 1) * (q.gy + 1) > static_cast<double>(uniform.gx) * uniform.gy);
      CHECK(q.inv_w * (box.max_x - box.min_x) == Approx(q.gx));
      CHECK(q.cell_h * q.gy == Approx(box.max_y - box.min_y));
    }
  }
}

TEST_CASE("CUDA uniform cells: coarser for non-integer sites, never more cells than the room made for them",
          "[cuda][grid]") {
  // CellBuckets makes room (cell starts, key bits) for make_grid_shape's cells and fills the
  // starts of the shape it applies; uniform cells must fit that room, whatever the box.
  for (const double aspect : {1.0, 0.076, 13.0, 1e-3, 1e3}) {
    const Box box{-1.0, 2.0, -1.0 + aspect, 3.0};
    for (const std::size_t n : {std::size_t{3}, std::size_t{1000}, std::size_t{123457}, std::size_t{1} << 24}) {
      for (const double per_bucket : {0.5, 2.0, 3.0}) {
        const cuda::GridShape room = cuda::make_grid_shape(box, n, per_bucket);
        const cuda::GridShape coarse = cuda::uniform_cells_shape(box, n, per_bucket, false);
        const cuda::GridShape integer = cuda::uniform_cells_shape(box, n, per_bucket, true);
        INFO("aspect " << aspect << ", n " << n << ", " << per_bucket << " a cell: room " << room.gx << " x " << room.gy
                       << ", coarse " << coarse.gx << " x " << coarse.gy);
        CHECK(coarse.gx <= room.gx);
        CHECK(coarse.gy <= room.gy);
        CHECK(integer.gx == room.gx);
        CHECK(integer.gy == room.gy);
        // About kUniformCellsScale times fewer cells, where there are enough to count and no
        // axis is at make_grid_shape's cap of 16384.
        if (room.gx >= 100 && room.gy >= 100 && room.gx < 16384 && room.gy < 16384)
          CHECK(static_cast<double>(room.gx) * room.gy / (static_cast<double>(coarse.gx) * coarse.gy) ==
                Approx(cuda::kUniformCellsScale).epsilon(0.05));
      }
    }
  }
}

TEST_CASE("CUDA grid choice: uniform cells for evenly spread sites, quantile cells for clusters", "[cuda][grid]") {
  // The evenness test as the device runs it (evenness_bin over the quantile sample, then
  // evenly_spread), here on the CPU.
  auto chooses_uniform = [](const std::vector<Point2>& points) {
    const SiteSet sites = prepare_sites(points);
    const std::size_t n = sites.points.size();
    const cuda::GridShape shape = cuda::make_grid_shape(sites.bounds, n, 2.0);
    const cuda::EvennessFrame frame = cuda::evenness_frame(cuda::make_grid_view(shape, sites.bounds));
    const int samples = cuda::quantile_sample_count(n);
    std::vector<unsigned> bins(cuda::kEvennessBins * cuda::kEvennessBins, 0);
    for (int i = 0; i < samples; ++i) {
      const Point2 p = sites.points[cuda::quantile_sample_site(i, static_cast<int>(n), samples)];
      const int b = cuda::evenness_bin(frame, p.x, p.y);
      REQUIRE(b >= 0);
      REQUIRE(b < cuda::kEvennessBins * cuda::kEvennessBins);
      ++bins[b];
    }
    return cuda::evenly_spread(*std::max_element(bins.begin(), bins.end()), samples);
  };
  for (const std::uint64_t seed : {1u, 2u, 3u}) {
    CHECK(chooses_uniform(generate_points("uniform", std::size_t{1} << 16, seed)));
    CHECK(chooses_uniform(generate_points("grid", std::size_t{1} << 16, seed)));
    CHECK_FALSE(chooses_uniform(generate_points("gaussian", std::size_t{1} << 16, seed)));
    CHECK_FALSE(chooses_uniform(generate_points("kuzmin", std::size_t{1} << 16, seed)));
  }
  // Too few sites to tell: quantile cells, as before the test existed.
  CHECK_FALSE(chooses_uniform(generate_points("uniform", std::size_t{1} << 12, 1)));
}

TEST_CASE("CUDA star walk on the CPU: small integer lattices are decided in the scan, exactly", "[cuda][star]") {
  // exact_lattice_arithmetic: integer sites spanning at most 5000 units, where the apex
  // filters' arithmetic is exact, so ties go to CGAL's perturbation in the scan itself.
  namespace p = test::points;
  CHECK_FALSE(exact_lattice_arithmetic(prepare_sites(p::uniform(1000, 5))));
  std::vector<Point2> wide = p::grid(1000, 5);
  wide.push_back({5001.0, 0.0});  // 5001 units across
  CHECK_FALSE(exact_lattice_arithmetic(prepare_sites(wide)));
  // (rotated_grid_exact: one hull site has more neighbours than a star row holds.)
  for (const Family& family : {Family{"grid", p::grid, 10000, 0.0, 0.0},
                               Family{"rotated_grid_exact", p::rotated_grid_exact, 4000, 0.001, 0.001},
                               Family{"square_boundary", p::square_boundary, 2000, 0.0, 0.0}}) {
    DYNAMIC_SECTION(family.name) {
      const SiteSet sites = prepare_sites(family.make(family.n, 5));
      REQUIRE(exact_lattice_arithmetic(sites));
      // Exact against CGAL, and no site deferred for a candidate left undecided, on both grids.
      for (const bool quantile : {true, false}) {
        CHECK(check_family(family, quantile, cuda::StarSearch::boxes).deferred_undecided == 0);
      }
    }
  }
}
