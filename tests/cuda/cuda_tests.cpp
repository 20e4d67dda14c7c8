// CUDA backend tests. Exit 0: all passed; 1: a failure; 77: no CUDA device (ctest: skipped).
//
//   expanse_cuda_tests            every test
//   expanse_cuda_tests --small    a few small cases (for compute-sanitizer)
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "backends/backend.hpp"
#include "cuda_internal.hpp"
#include "expanse/check.hpp"
#include "expanse/cuda_interop.hpp"
#include "expanse/error.hpp"
#include "expanse/generate.hpp"
#include "expanse/triangulate.hpp"
#include "hull/convex_hull.hpp"
#include "input/morton.hpp"
#include "input/site_set.hpp"
#include "predicates/predicates.hpp"
#include "seam/adjacency_audit.hpp"

using namespace expanse;
using namespace expanse::detail;

namespace {

int failures = 0;

void fail(const std::string& test, const std::string& what) {
  ++failures;
  std::printf("FAIL %s: %s\n", test.c_str(), what.c_str());
}

/// Checks a backend's partial triangulation on its own terms: every triangle CCW, distinct,
/// with an empty perturbed circumcircle (brute force for small inputs), neighbours consistent,
/// and complete (2n - h - 2) when nothing was deferred.
void check_partial(const std::string& test, const SiteSet& sites, const Hull& hull,
                   const PartialTriangulation& partial, bool brute_force, bool paper) {
  const auto& p = sites.points;
  const std::size_t n = p.size();
  std::set<std::array<int, 3>> seen;
  std::map<std::pair<int, int>, int> edge_owner;
  for (std::size_t t = 0; t < partial.triangles.size(); ++t) {
    auto tri = partial.triangles[t];
    for (int v : tri)
      if (v < 0 || static_cast<std::size_t>(v) >= n) return fail(test, "vertex id out of range");
    if (orient2d(p[tri[0]], p[tri[1]], p[tri[2]]) <= 0) return fail(test, "triangle not CCW: " + std::to_string(t));
    auto key = tri;
    std::rotate(key.begin(), std::min_element(key.begin(), key.end()), key.end());
    if (!seen.insert(key).second) return fail(test, "triangle emitted twice: " + std::to_string(t));
    for (int k = 0; k < 3; ++k) {
      const int a = tri[(k + 1) % 3], b = tri[(k + 2) % 3];
      if (!edge_owner.emplace(std::make_pair(a, b), static_cast<int>(t)).second)
        return fail(test, "directed edge used twice");
    }
    if (brute_force) {
      for (std::size_t d = 0; d < n; ++d) {
        if (static_cast<int>(d) == tri[0] || static_cast<int>(d) == tri[1] || static_cast<int>(d) == tri[2]) continue;
        if (incircle_perturbed(p[tri[0]], p[tri[1]], p[tri[2]], p[d]) > 0)
          return fail(test, "triangle " + std::to_string(t) + " is not Delaunay (site " + std::to_string(d) + " inside)");
      }
    }
  }
  if (!partial.neighbors.empty()) {
    if (partial.neighbors.size() != partial.triangles.size()) return fail(test, "neighbors size mismatch");
    for (std::size_t t = 0; t < partial.triangles.size(); ++t) {
      const auto tri = partial.triangles[t];
      for (int k = 0; k < 3; ++k) {
        const int a = tri[(k + 1) % 3], b = tri[(k + 2) % 3];
        const int nb = partial.neighbors[t][k];
        auto it = edge_owner.find({b, a});
        const int expect = it == edge_owner.end() ? -1 : it->second;
        if (nb != expect) {
          // -1 is allowed where the other triangle exists but its owner deferred; never a wrong id.
          if (nb != -1 || partial.deferred_expansions == 0)
            return fail(test, "neighbor of triangle " + std::to_string(t) + " across " + std::to_string(k) + " is " +
                                  std::to_string(nb) + ", expected " + std::to_string(expect));
        }
      }
    }
  }
  // The paper's layout may leave edges open without deferring (seeds it could not place).
  if (partial.deferred_expansions == 0 && !paper) {
    const std::size_t expect = 2 * n - hull.sites.size() - 2;
    if (partial.triangles.size() != expect)
      return fail(test, "triangle count " + std::to_string(partial.triangles.size()) + ", expected " + std::to_string(expect));
  }
}

void grow_case(Backend& backend, const std::string& name, const std::vector<Point2>& input, const Layout& layout,
               bool brute_force, bool expect_no_deferral) {
  const std::string test = name + " n=" + std::to_string(input.size()) +
                           (layout.seeding == Layout::Seeding::paper_blocks ? " paper" : " per-site");
  try {
    SiteSet sites = prepare_sites(input);
    Hull hull = convex_hull(sites);
    if (hull.collinear || sites.size() < 3) return;
    GrowResult r = backend.grow(GrowInput{sites, hull, layout});
    const int before = failures;
    const bool paper = layout.seeding == Layout::Seeding::paper_blocks;
    check_partial(test, sites, hull, r.partial, brute_force, paper);
    if (expect_no_deferral && !paper && r.partial.deferred_expansions != 0)
      fail(test, std::to_string(r.partial.deferred_expansions) + " deferred expansions (expected none)");
    if (r.device_stages.empty()) fail(test, "no device stage times");
    if (failures == before)
      std::printf("ok   %s: %zu triangles, %zu deferred\n", test.c_str(), r.partial.triangles.size(),
                  r.partial.deferred_expansions);
  } catch (const Error& e) {
    fail(test, std::string("threw ") + to_string(e.code()) + ": " + e.what());
  }
}

/// The device's preparation (grow_from_input) against the host's (prepare_sites): the same
/// sites in Morton order (equal codes may come in either order), the same representatives, and a
/// valid growth on them. `sort`: EXPANSE_CUDA_MORTON_SORT for the run ("short", "full" or null:
/// the forecast decides); `short_expected`: whether the short sort must have ordered them.
void device_preparation_case(Backend& backend, const std::string& name, const std::vector<Point2>& input,
                             const char* sort, bool short_expected, bool hash_expected = false) {
  const std::string test = "device preparation, " + std::string(sort ? sort : "forecast") + " sort: " + name;
  if (sort) setenv("EXPANSE_CUDA_MORTON_SORT", sort, 1);
  try {
    const InputScan scan = scan_input(input);
    const InputHull input_hull = convex_hull_of_input(input, scan);
    const Layout layout;
    auto made = backend.grow_from_input(
        {input, scan, [&] { return input_hull.collinear ? nullptr : &input_hull.sites; }, layout, nullptr});
    unsetenv("EXPANSE_CUDA_MORTON_SORT");
    if (!made) return fail(test, "the device declined");
    const SiteSet host = prepare_sites(input);
    const SiteSet& device = made->sites;
    const Quantiser q(host.bounds);
    auto code = [&](const Point2& p) { return morton_code(q.x(p.x), q.y(p.y)); };
    if (device.points.size() != host.points.size()) return fail(test, "site counts differ");
    for (std::size_t k = 0; k < host.points.size(); ++k)
      if (code(device.points[k]) != code(host.points[k]))
        return fail(test, "site " + std::to_string(k) + " out of Morton order");
    auto sorted = [](const auto& points) {
      std::vector<Point2> p(points.begin(), points.end());
      std::sort(p.begin(), p.end(), [](const Point2& a, const Point2& b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
      return p;
    };
    if (sorted(device.points) != sorted(host.points)) return fail(test, "the sites differ");
    if (!std::equal(device.representative.begin(), device.representative.end(), host.representative.begin(),
                    host.representative.end()))
      return fail(test, "representatives differ");
    if (detail::cuda::last_run_counters().short_morton_sort != short_expected)
      return fail(test, short_expected ? "the short sort did not serve" : "the short sort served");
    if (detail::cuda::last_run_counters().merge_hash_tables != hash_expected)
      return fail(test, hash_expected ? "the merge looked back through a run too long for it"
                                      : "the merge took the hash tables");
    check_partial(test, device, made->hull, made->grown.partial, false, false);
    std::printf("ok   %s: %zu sites (%s sort, merged by %s)\n", test.c_str(), device.points.size(),
                short_expected ? "short" : "full", hash_expected ? "hash tables" : "looking back");
  } catch (const Error& e) {
    unsetenv("EXPANSE_CUDA_MORTON_SORT");
    fail(test, std::string("threw ") + e.what());
  }
}

/// 1000 uniform points and a cluster far finer than the quantisation: 1000 distinct points 1e-13
/// apart that share a Morton code or two, a run too long for the merge to look back through.
std::vector<Point2> uniform_with_fine_cluster() {
  std::vector<Point2> points = generate_points("uniform", 1000, 15);
  for (int k = 0; k < 1000; ++k) points.push_back({0.5 + (k % 40) * 1e-13, 0.25 + (k / 40) * 1e-13});
  return points;
}

std::vector<Point2> square_grid(int side) {
  std::vector<Point2> p;
  for (int y = 0; y < side; ++y)
    for (int x = 0; x < side; ++x) p.push_back({static_cast<double>(x), static_cast<double>(y)});
  return p;
}

std::vector<Point2> circle_and_centre(int count) {
  // Exactly cocircular points: the lattice points on a circle of radius 5^k (Pythagorean).
  std::vector<Point2> p{{0, 0}};
  const int r = 65;
  for (int x = -r; x <= r; ++x)
    for (int y = -r; y <= r; ++y)
      if (x * x + y * y == r * r) p.push_back({static_cast<double>(x), static_cast<double>(y)});
  (void)count;
  return p;
}

void full_pipeline_case(const std::string& name, const std::vector<Point2>& points, const Options& options) {
  const std::string test = "triangulate " + name + " n=" + std::to_string(points.size());
  try {
    Mesh mesh = triangulate(points, options);
    CheckReport report = check_mesh(points, mesh);
    if (!report.ok) return fail(test, report.problems.empty() ? "check_mesh failed" : report.problems.front());
    std::printf("ok   %s: %zu triangles (gpu %zu, seam %zu, deferred %zu)\n", test.c_str(), mesh.triangles.size(),
                mesh.stats.gpu_triangles, mesh.stats.seam_triangles, mesh.stats.deferred_expansions);
  } catch (const Error& e) {
    fail(test, std::string("threw ") + to_string(e.code()) + ": " + e.what());
  }
}

}  // namespace

int main(int argc, char** argv) {
  const bool small = argc > 1 && std::strcmp(argv[1], "--small") == 0;
  std::vector<DeviceDescription> devices;
  try {
    devices = list_cuda_devices();
  } catch (const Error& e) {
    std::printf("SKIP: %s\n", e.what());
    return 77;
  }
  if (devices.empty()) {
    std::printf("SKIP: no CUDA device\n");
    return 77;
  }
  for (const auto& d : devices) std::printf("device %d: %s (%s)\n", d.index, d.name.c_str(), d.details.c_str());

  std::unique_ptr<Backend> backend;
  try {
    backend = make_cuda_backend(-1);  // runs the device self-test
    std::printf("ok   backend + device self-test on %s\n", backend->device_name().c_str());
  } catch (const Error& e) {
    std::printf("FAIL backend creation: %s\n", e.what());
    return 1;
  }

  Layout per_site;
  Layout paper = Layout::paper();
  std::vector<Layout> layouts{per_site};
  if (std::getenv("EXPANSE_CUDA_TEST_PAPER")) layouts.push_back(paper);
  for (const Layout& layout : layouts) {
    grow_case(*backend, "uniform", generate_points("uniform", 300, 1), layout, true, false);
    grow_case(*backend, "grid", square_grid(24), layout, true, true);
    grow_case(*backend, "circle+centre", circle_and_centre(0), layout, true, false);
    grow_case(*backend, "clusters", generate_points("gaussian", 500, 2), layout, true, false);
    if (small) continue;
    for (const char* dist : {"uniform", "gaussian", "clusters", "grid", "rotated_grid", "disk", "kuzmin",
                             "duplicates", "near_collinear", "thin_circle", "tiny", "huge", "offset"}) {
      try {
        grow_case(*backend, dist, generate_points(dist, 1500, 7), layout, true, false);
      } catch (const Error& e) {
        fail(dist, e.what());
      }
    }
    grow_case(*backend, "grid", square_grid(256), layout, false, true);
    // Nearly cocircular floats: every square's incircle is left to the exact path, which decides
    // it from exact coordinate differences (incircle_exact_differences); none may defer.
    if (layout.seeding != Layout::Seeding::paper_blocks) {
      std::vector<Point2> decimal = square_grid(200);
      for (Point2& q : decimal) q = {10.0 + 0.1 * q.x, 10.0 + 0.1 * q.y};
      grow_case(*backend, "decimal grid", decimal, layout, false, true);
    }
    grow_case(*backend, "uniform", generate_points("uniform", 200000, 3), layout, false, false);
    grow_case(*backend, "kuzmin", generate_points("kuzmin", 200000, 4), layout, false, false);
  }

  // Both bucket grids (quantile is the default) give valid stars.
  setenv("EXPANSE_CUDA_GRID", "uniform", 1);
  grow_case(*backend, "uniform grid: uniform", generate_points("uniform", 300, 1), per_site, true, false);
  grow_case(*backend, "uniform grid: grid", square_grid(24), per_site, true, true);
  if (!small) grow_case(*backend, "uniform grid: kuzmin", generate_points("kuzmin", 1500, 7), per_site, true, false);
  unsetenv("EXPANSE_CUDA_GRID");

  // Quantile cells' tall boxes in the outer columns scanned across (TailColumns: by default
  // where the x-tails are heavy, as kuzmin's above) and a row at a time, as before; and across
  // on a gaussian's cells, which take no copy by default.
  setenv("EXPANSE_CUDA_TAIL_COLUMNS", "0", 1);
  grow_case(*backend, "no tail columns: kuzmin", generate_points("kuzmin", 1500, 7), per_site, true, false);
  setenv("EXPANSE_CUDA_TAIL_COLUMNS", "1", 1);
  grow_case(*backend, "tail columns: clusters", generate_points("gaussian", 1500, 7), per_site, true, false);
  if (!small)
    grow_case(*backend, "tail columns: clusters 200000", generate_points("gaussian", 200000, 4), per_site, false,
              false);
  unsetenv("EXPANSE_CUDA_TAIL_COLUMNS");

  // Every register cap gives valid stars.
  for (const char* blocks : {"6", "8"}) {
    setenv("EXPANSE_CUDA_BLOCKS_PER_SM", blocks, 1);
    grow_case(*backend, std::string("blocks per SM ") + blocks + ": clusters", generate_points("gaussian", 500, 2),
              per_site, true, false);
  }
  unsetenv("EXPANSE_CUDA_BLOCKS_PER_SM");
  // One pass only, and a first pass so short that nearly every site goes to the second, where a
  // warp walks each site 32 candidates at a time (exact decisions and narrowing included: the
  // grid's cocircular squares and the hull-hugging sites take those paths).
  for (const char* first : {"0", "8"}) {
    setenv("EXPANSE_CUDA_FIRST_BUDGET", first, 1);
    const std::string label = std::string("first-pass budget ") + first + ": ";
    grow_case(*backend, label + "uniform", generate_points("uniform", 1500, 3), per_site, true, false);
    grow_case(*backend, label + "kuzmin", generate_points("kuzmin", 1500, 7), per_site, true, false);
    grow_case(*backend, label + "grid", square_grid(24), per_site, true, true);
    if (small) continue;
    for (const char* dist : {"duplicates", "near_collinear", "thin_circle", "rotated_grid"})
      grow_case(*backend, label + dist, generate_points(dist, 1500, 7), per_site, true, false);
    grow_case(*backend, label + "uniform 200000", generate_points("uniform", 200000, 3), per_site, false, false);
  }
  unsetenv("EXPANSE_CUDA_FIRST_BUDGET");

  // The edge's retry (nearly every edge site's, at a first-pass budget of 8) on the edge's own
  // stream as before, and on the low stream with one block a multiprocessor (the default has 2).
  setenv("EXPANSE_CUDA_FIRST_BUDGET", "8", 1);
  for (const char* edge_retry : {"edge", "low:1"}) {
    setenv("EXPANSE_CUDA_EDGE_RETRY", edge_retry, 1);
    const std::string label = std::string("edge retry ") + edge_retry + ": ";
    grow_case(*backend, label + "uniform", generate_points("uniform", 1500, 3), per_site, true, false);
    grow_case(*backend, label + "kuzmin", generate_points("kuzmin", 1500, 7), per_site, true, false);
    if (small) continue;
    grow_case(*backend, label + "kuzmin 200000", generate_points("kuzmin", 200000, 4), per_site, false, false);
  }
  unsetenv("EXPANSE_CUDA_EDGE_RETRY");
  unsetenv("EXPANSE_CUDA_FIRST_BUDGET");

  // Two phases (StarInbox; the default above 2^18 sites): the odd sites' walks start from and
  // step through what the even sites posted, alone and with the first pass's hand-offs (a first
  // budget of 8 sends nearly every site to the warps); the stars that inboxes hold whole recorded
  // first and the rest walked from a list (inbox_star_kernel).
  setenv("EXPANSE_CUDA_PHASES", "2", 1);
  for (const char* first : {"", "8"}) {
    {
      if (*first) setenv("EXPANSE_CUDA_FIRST_BUDGET", first, 1);
      const std::string label = std::string("two phases") + (*first ? ", first-pass budget 8" : "") + ": ";
      grow_case(*backend, label + "uniform", generate_points("uniform", 1500, 3), per_site, true, false);
      grow_case(*backend, label + "kuzmin", generate_points("kuzmin", 1500, 7), per_site, true, false);
      grow_case(*backend, label + "grid", square_grid(24), per_site, true, true);
      if (small) continue;
      for (const char* dist : {"clusters", "duplicates", "near_collinear", "thin_circle", "rotated_grid", "offset"})
        grow_case(*backend, label + dist, generate_points(dist, 1500, 7), per_site, true, false);
      grow_case(*backend, label + "grid 256", square_grid(256), per_site, false, true);
      grow_case(*backend, label + "uniform 200000", generate_points("uniform", 200000, 3), per_site, false, false);
      grow_case(*backend, label + "kuzmin 200000", generate_points("kuzmin", 200000, 4), per_site, false, false);
    }
  }
  unsetenv("EXPANSE_CUDA_FIRST_BUDGET");
  unsetenv("EXPANSE_CUDA_PHASES");

  // The boundary strips (BoundaryStrips): at any size, so that the sanitizers' small cases take
  // them too (hull-hugging sites of a uniform square, in the edge's first pass and the warps'
  // second), and switched off. Kuzmin's quantile cells take none, forced or not.
  for (const char* strips : {"1", "0"}) {
    setenv("EXPANSE_CUDA_STRIPS", strips, 1);
    const std::string label = std::string("boundary strips ") + (*strips == '1' ? "on" : "off") + ": ";
    grow_case(*backend, label + "uniform 20000", generate_points("uniform", 20000, 5), per_site, false, false);
    setenv("EXPANSE_CUDA_FIRST_BUDGET", "8", 1);
    grow_case(*backend, label + "first-pass budget 8, uniform 1500", generate_points("uniform", 1500, 3), per_site, true,
              false);
    unsetenv("EXPANSE_CUDA_FIRST_BUDGET");
    if (small) continue;
    grow_case(*backend, label + "uniform 200000", generate_points("uniform", 200000, 3), per_site, false, false);
    grow_case(*backend, label + "kuzmin 200000", generate_points("kuzmin", 200000, 4), per_site, false, false);
  }
  unsetenv("EXPANSE_CUDA_STRIPS");

  // The work budget defers runaway sites, and its counters read back (they once read garbage).
  {
    const std::string test = "work budget 40, uniform n=20000";
    setenv("EXPANSE_CUDA_BUDGET", "40", 1);
    try {
      SiteSet sites = prepare_sites(generate_points("uniform", 20000, 11));
      Hull hull = convex_hull(sites);
      GrowResult r = backend->grow(GrowInput{sites, hull, per_site});
      const auto& c = detail::cuda::last_run_counters();
      const int before = failures;
      check_partial(test, sites, hull, r.partial, false, false);
      if (c.sites_over_budget == 0 || c.sites_over_budget > r.partial.deferred_expansions)
        fail(test, "sites_over_budget " + std::to_string(c.sites_over_budget) + " vs deferred " +
                       std::to_string(r.partial.deferred_expansions));
      if (c.max_cells_per_site == 0 || c.max_cells_per_site > 40 + 1 + 20000)
        fail(test, "max work per site " + std::to_string(c.max_cells_per_site));
      if (failures == before)
        std::printf("ok   %s: %zu deferred, %llu over budget, max work %llu\n", test.c_str(),
                    r.partial.deferred_expansions, static_cast<unsigned long long>(c.sites_over_budget),
                    static_cast<unsigned long long>(c.max_cells_per_site));
    } catch (const Error& e) {
      fail(test, std::string("threw ") + e.what());
    }
    unsetenv("EXPANSE_CUDA_BUDGET");
    SiteSet sites = prepare_sites(generate_points("uniform", 20000, 11));
    Hull hull = convex_hull(sites);
    backend->grow(GrowInput{sites, hull, per_site});
    const auto& c = detail::cuda::last_run_counters();
    // The default box scans count row segments too: the same bound as the CPU test of the walk
    // (tests/unit/test_cuda_star_walk.cpp), which sees ~6,500 on 20,000 uniform sites.
    if (c.sites_over_budget != 0 || c.max_cells_per_site == 0 || c.max_cells_per_site > 8000)
      fail("work counters, uniform n=20000", "over budget " + std::to_string(c.sites_over_budget) + ", max work " +
                                                 std::to_string(c.max_cells_per_site));
    else
      std::printf("ok   work counters, uniform n=20000: max work per site %llu\n",
                  static_cast<unsigned long long>(c.max_cells_per_site));
  }

  // Deferred sites leave edges open from both sides (both ends deferred): the device links such
  // pairs, and the adjacency it keeps must be exactly what the host audit accepts. The audit
  // lists the open edges as it finds them; with room for fewer than there are, a second audit
  // lists them all (EXPANSE_CUDA_AUDIT_ROOM=8).
  for (const char* room : {"", "8"}) {
    const std::string test = std::string("open pairs linked, work budget 150, uniform n=20000") +
                             (*room ? std::string(", audit room ") + room : std::string());
    if (*room) setenv("EXPANSE_CUDA_AUDIT_ROOM", room, 1);
    setenv("EXPANSE_CUDA_BUDGET", "150", 1);
    setenv("EXPANSE_CUDA_FIRST_BUDGET", "0", 1);
    try {
      SiteSet sites = prepare_sites(generate_points("uniform", 20000, 6));
      Hull hull = convex_hull(sites);
      GrowResult r = backend->grow(GrowInput{sites, hull, per_site});
      const auto& c = detail::cuda::last_run_counters();
      const int before = failures;
      check_partial(test, sites, hull, r.partial, false, false);
      if (r.partial.deferred_expansions == 0) fail(test, "nothing deferred: the case tests nothing");
      if (c.open_pairs_linked == 0) fail(test, "no open pair linked");
      if (*room && c.open_edges <= std::strtoull(room, nullptr, 10))
        fail(test, "the open edges fit the room: the second audit is not exercised");
      if (!r.adjacency_audited || r.partial.neighbors.empty()) fail(test, "device audit failed after linking");
      if (!detail::adjacency_is_trustworthy(r.partial, hull)) fail(test, "host audit rejects the linked adjacency");
      if (failures == before)
        std::printf("ok   %s: %zu deferred, %llu open edges, %llu pairs linked\n", test.c_str(),
                    r.partial.deferred_expansions, static_cast<unsigned long long>(c.open_edges),
                    static_cast<unsigned long long>(c.open_pairs_linked));
    } catch (const Error& e) {
      fail(test, std::string("threw ") + e.what());
    }
    unsetenv("EXPANSE_CUDA_BUDGET");
    unsetenv("EXPANSE_CUDA_FIRST_BUDGET");
    unsetenv("EXPANSE_CUDA_AUDIT_ROOM");
  }

  {
    // The device's two sorts. Pairs of points 1e-7 apart share a short key but not a code (runs
    // that the short sort orders by the whole code; so many that the forecast refuses it); 40
    // copies of one point make a run of equal keys too long for it (the full sort after all);
    // an even spread passes the forecast, kuzmin's centre does not.
    std::vector<Point2> pairs = generate_points("uniform", 3000, 16);
    for (int k = 0; k < 500; ++k) pairs.push_back({pairs[k].x + 1e-7 * (k % 3), pairs[k].y - 1e-7 * (k % 5)});
    std::vector<Point2> copies = generate_points("uniform", 3000, 17);
    copies.insert(copies.end(), 40, copies[5]);
    device_preparation_case(*backend, "uniform with close pairs", pairs, "short", true);
    device_preparation_case(*backend, "uniform with close pairs", pairs, "full", false);
    device_preparation_case(*backend, "uniform with close pairs", pairs, nullptr, false);
    device_preparation_case(*backend, "40 copies of one point", copies, "short", false);
    device_preparation_case(*backend, "duplicates", generate_points("duplicates", 3000, 18), "short", true);
    device_preparation_case(*backend, "uniform", generate_points("uniform", 20000, 20), nullptr, true);
    device_preparation_case(*backend, "kuzmin", generate_points("kuzmin", 20000, 19), nullptr, false);
    // 200 copies of one point among distinct ones: a run of equal codes longer than the short
    // sort takes, short enough to look back through, every copy merged into the first.
    std::vector<Point2> crowded = generate_points("uniform", 3000, 21);
    crowded.insert(crowded.end(), 200, crowded[11]);
    device_preparation_case(*backend, "200 copies of one point", crowded, nullptr, false);
    // The merge's hash tables, with no point repeating (no groups made, no scan).
    device_preparation_case(*backend, "a cluster finer than the quantisation", uniform_with_fine_cluster(), nullptr,
                            false, true);
  }

  {
    // The pipeline with the device preparing the sites (prepare_on_device.cu): small enough for
    // compute-sanitizer; duplicates merged, a long run of copies sorted again by coordinates.
    Options options;
    options.backend = BackendKind::cuda;
    full_pipeline_case("device preparation: uniform", generate_points("uniform", 2000, 12), options);
    full_pipeline_case("device preparation: duplicates", generate_points("duplicates", 2000, 13), options);
    std::vector<Point2> crowded = generate_points("uniform", 1000, 14);
    crowded.insert(crowded.end(), 100, crowded[7]);
    full_pipeline_case("device preparation: 101 copies of one point", crowded, options);
    // The fine cluster with 60 copies among its points: the merge's hash tables for each run.
    // The representatives must be the host preparation's, input for input.
    std::vector<Point2> fine = uniform_with_fine_cluster();
    for (int k = 0; k < 60; ++k) fine.push_back(fine[1000 + (k * 7) % 1000]);
    const std::string test = "device preparation: a cluster finer than the quantisation, with copies";
    full_pipeline_case(test, fine, options);
    try {
      const Mesh mesh = triangulate(fine, options);
      const SiteSet host = prepare_sites(fine);
      if (mesh.representative != host.representative)
        fail(test, "representatives differ from the host preparation's");
      else if (host.points.size() != fine.size() - 60)
        fail(test, "the case has not the copies it was built with");
      else if (!detail::cuda::last_run_counters().merge_hash_tables)
        fail(test, "the merge did not take the hash tables");
      else
        std::printf("ok   %s: representatives as the host's (%zu sites)\n", test.c_str(), host.points.size());
    } catch (const Error& e) {
      fail(test, std::string("threw ") + e.what());
    }
  }

  if (!small) {
    Options options;
    options.backend = BackendKind::cuda;
    full_pipeline_case("uniform", generate_points("uniform", 20000, 5), options);
    full_pipeline_case("grid", generate_points("grid", 10000, 5), options);
    full_pipeline_case("circle", generate_points("circle", 2000, 5), options);
    // Some sites deferred: the device audit must list the seam's open edges, find none open
    // from both sides, and the seam stage then completes the mesh on the device's adjacency.
    setenv("EXPANSE_CUDA_BUDGET", "150", 1);
    Options with_neighbors = options;
    with_neighbors.neighbors = true;
    full_pipeline_case("uniform, work budget 150", generate_points("uniform", 20000, 6), with_neighbors);
    unsetenv("EXPANSE_CUDA_BUDGET");
    // The interior sites' second pass with a budget of its own (interior_retry_budget; here 96
    // units, while the edge's keep the whole): the sites it gives up on defer, and the seam
    // stage makes their triangles.
    setenv("EXPANSE_CUDA_RETRY_BUDGET", "96", 1);
    setenv("EXPANSE_CUDA_FIRST_BUDGET", "64", 1);
    {
      const std::string test = "interior second pass, budget 96: gaussian n=20000";
      try {
        const std::vector<Point2> points = generate_points("gaussian", 20000, 8);
        const Mesh mesh = triangulate(points, with_neighbors);
        const CheckReport report = check_mesh(points, mesh);
        if (!report.ok)
          fail(test, report.problems.empty() ? "check_mesh failed" : report.problems.front());
        else if (mesh.stats.deferred_expansions == 0)
          fail(test, "nothing deferred: the case tests nothing");
        else
          std::printf("ok   %s: %zu triangles (seam %zu, deferred %zu)\n", test.c_str(), mesh.triangles.size(),
                      mesh.stats.seam_triangles, mesh.stats.deferred_expansions);
      } catch (const Error& e) {
        fail(test, std::string("threw ") + e.what());
      }
    }
    unsetenv("EXPANSE_CUDA_RETRY_BUDGET");
    unsetenv("EXPANSE_CUDA_FIRST_BUDGET");
    // Interop: points already on the device, work on the caller's stream.
    try {
      auto points = generate_points("uniform", 5000, 9);
      cudaStream_t stream = nullptr;
      cudaStreamCreateWithFlags(&stream, cudaStreamNonBlocking);
      double* d_xy = nullptr;
      cudaMalloc(reinterpret_cast<void**>(&d_xy), points.size() * sizeof(Point2));
      cudaMemcpy(d_xy, points.data(), points.size() * sizeof(Point2), cudaMemcpyHostToDevice);
      Mesh mesh = expanse::cuda::triangulate_device(d_xy, points.size(), stream);
      cudaFree(d_xy);
      cudaStreamDestroy(stream);
      CheckReport report = check_mesh(points, mesh);
      if (!report.ok) fail("interop", report.problems.empty() ? "check_mesh failed" : report.problems.front());
      else std::printf("ok   interop triangulate_device on a caller stream: %zu triangles\n", mesh.triangles.size());
    } catch (const Error& e) {
      fail("interop", e.what());
    }
  }

  std::printf("%s: %d failure(s)\n", failures ? "FAILED" : "PASSED", failures);
  return failures ? 1 : 0;
}
