// The per-site layout's device passes that replace host stages: bucketing (shaders/bucket.comp,
// scan.comp) must give exactly the host's counting sort (same cells, SiteSet order within a
// cell), and the backend the same triangles and deferrals either way (the output order is the
// star kernel's atomics' and varies from run to run); the adjacency audit (shaders/audit.comp
// and the host's open-edge check) must pass a correct adjacency and catch broken ones.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <mutex>
#include <optional>
#include <tuple>
#include <random>
#include <string>
#include <vector>

#include "backends/backend.hpp"
#include "backends/vulkan/vulkan_backend.hpp"
#include "expanse/triangulate.hpp"
#include "harness.hpp"
#include "hull/convex_hull.hpp"
#include "input/morton.hpp"
#include "input/site_set.hpp"
#include "seam/adjacency_audit.hpp"

namespace expanse::vulkan_tests {
namespace {

// The host's counting sort, written plainly: cell = clamp(floor((x - origin) * inv_width)),
// the rule of shaders/include/cells.glsl (this file builds with -ffp-contract=off).
detail::vk::DeviceBuckets bucket_reference(const detail::SiteSet& sites, const detail::Hull& hull, int cells) {
  const std::size_t n = std::size_t(sites.size());
  const double wx = sites.bounds.max_x - sites.bounds.min_x, wy = sites.bounds.max_y - sites.bounds.min_y;
  const double ix = wx > 0 ? double(cells) / wx : 0.0, iy = wy > 0 ? double(cells) / wy : 0.0;
  auto coord = [&](double v, double origin, double inv) {
    const double t = (v - origin) * inv;
    return int(std::clamp(std::floor(t), 0.0, double(cells - 1)));
  };
  std::vector<std::int32_t> cell(n);
  detail::vk::DeviceBuckets b;
  b.cell_start.assign(std::size_t(cells) * std::size_t(cells) + 1, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const Point2& p = sites.points[i];
    cell[i] = coord(p.y, sites.bounds.min_y, iy) * cells + coord(p.x, sites.bounds.min_x, ix);
    ++b.cell_start[std::size_t(cell[i]) + 1];
  }
  for (std::size_t c = 1; c < b.cell_start.size(); ++c) b.cell_start[c] += b.cell_start[c - 1];
  std::vector<std::int32_t> next(b.cell_start.begin(), b.cell_start.end() - 1), to_sorted(n);
  b.sites.resize(n);
  b.to_site.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::int32_t at = next[std::size_t(cell[i])]++;
    b.sites[std::size_t(at)] = sites.points[i];
    b.to_site[std::size_t(at)] = std::int32_t(i);
    to_sorted[i] = at;
  }
  b.predecessor.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    const std::int32_t p = hull.predecessor[std::size_t(b.to_site[k])];
    b.predecessor[k] = p < 0 ? -1 : to_sorted[std::size_t(p)];
  }
  return b;
}

void check_bucketing(const std::string& name, const std::vector<Point2>& points, int cells) {
  const detail::SiteSet sites = detail::prepare_sites(points);
  const detail::Hull hull = detail::convex_hull(sites);
  auto context = detail::vk::shared_context(-1);
  const detail::vk::DeviceBuckets device = detail::vk::bucket_on_device(*context, sites, hull, cells);
  const detail::vk::DeviceBuckets host = bucket_reference(sites, hull, cells);
  // A cell of more than 4096 sites (bucket.comp's MAX_CELL) must be reported, not ranked.
  const bool crowded = std::adjacent_find(host.cell_start.begin(), host.cell_start.end(),
                                          [](int a, int b) { return b - a > 4096; }) != host.cell_start.end();
  VK_CHECK_THAT(device.crowded == crowded, "%s, %d cells per side: crowded %d, expected %d",
                name.c_str(), cells, int(device.crowded), int(crowded));
  if (crowded) {
    std::printf("  %-40s %5d cells per side: a crowded cell, reported\n", name.c_str(), cells);
    return;
  }
  VK_CHECK_THAT(device.cell_start == host.cell_start, "%s, %d cells per side: cell starts differ",
                name.c_str(), cells);
  VK_CHECK_THAT(device.to_site == host.to_site, "%s, %d cells per side: order differs", name.c_str(), cells);
  VK_CHECK_THAT(device.sites == host.sites, "%s, %d cells per side: sorted sites differ", name.c_str(), cells);
  VK_CHECK_THAT(device.predecessor == host.predecessor, "%s, %d cells per side: predecessors differ",
                name.c_str(), cells);
  std::printf("  %-40s %5d cells per side: device bucketing = host counting sort\n", name.c_str(), cells);
}

bool has_stage(const detail::GrowResult& r, const std::string& name) {
  return std::any_of(r.host_stages.begin(), r.host_stages.end(),
                     [&](const StageTime& s) { return s.name == name; });
}

detail::GrowResult grow_with(const detail::SiteSet& sites, const detail::Hull& hull,
                             const char* bucket, bool staged) {
  setenv("EXPANSE_VULKAN_BUCKET", bucket, 1);
  setenv("EXPANSE_VULKAN_STAGED", staged ? "1" : "0", 1);
  const Layout layout{};
  return detail::make_vulkan_backend(-1)->grow({sites, hull, layout});
}

// Host and device bucketing, on both paths: the same output vectors, element for element.
// `crowded`: a cell holds more sites than the device ranks, so the device path must fall back
// to the host's bucketing.
void check_same_output(const std::string& name, const std::vector<Point2>& points, bool crowded) {
  const detail::SiteSet sites = detail::prepare_sites(points);
  const detail::Hull hull = detail::convex_hull(sites);
  for (bool staged : {false, true}) {
    const char* path = staged ? "staged" : "in place";
    const detail::GrowResult host = grow_with(sites, hull, "host", staged);
    const detail::GrowResult device = grow_with(sites, hull, "device", staged);
    VK_CHECK_THAT(has_stage(device, "vulkan: bucket (submit + wait)"),
                  "%s, %s: the device did not bucket", name.c_str(), path);
    const bool quantile = name.find("quantile cells") != std::string::npos;
    VK_CHECK_THAT(has_stage(device, "vulkan: grid (quantile cells)") == quantile &&
                      has_stage(host, "vulkan: grid (quantile cells)") == quantile,
                  "%s, %s: %s cells expected", name.c_str(), path, quantile ? "quantile" : "uniform");
    VK_CHECK_THAT(has_stage(device, "vulkan: bucket") == crowded,
                  "%s, %s: host fallback %s", name.c_str(), path, crowded ? "expected" : "unexpected");
    VK_CHECK_THAT(canonical(host.partial.triangles) == canonical(device.partial.triangles),
                  "%s, %s: %zu triangles bucketed on the host, %zu on the device, or others",
                  name.c_str(), path, host.partial.triangles.size(), device.partial.triangles.size());
    VK_CHECK_THAT(device.partial.neighbors.empty() ||
                      detail::adjacency_is_trustworthy(device.partial, hull),
                  "%s, %s: the adjacency fails the host audit", name.c_str(), path);
    VK_CHECK_THAT(host.partial.deferred_expansions == device.partial.deferred_expansions,
                  "%s, %s: %zu deferred sites on the host's grid, %zu on the device's", name.c_str(),
                  path, host.partial.deferred_expansions, device.partial.deferred_expansions);
    if (device.adjacency_audited)
      VK_CHECK_THAT(detail::adjacency_is_trustworthy(device.partial, hull),
                    "%s, %s: the device audit passed an adjacency the host audit rejects",
                    name.c_str(), path);
    // The staged path audits on the device when it bucketed there, unless its list of open
    // edges overflowed (inputs where most sites defer).
    if (staged && !crowded && device.partial.deferred_expansions * 8 < sites.size())
      VK_CHECK_THAT(device.adjacency_audited, "%s, %s: the device did not audit", name.c_str(), path);
    std::printf("  %-40s %-9s triangles %7zu  deferred %5zu  audited on the device: %s\n",
                name.c_str(), path, device.partial.triangles.size(),
                device.partial.deferred_expansions, device.adjacency_audited ? "yes" : "no");
  }
  unsetenv("EXPANSE_VULKAN_BUCKET");
  unsetenv("EXPANSE_VULKAN_STAGED");
}

// The stars in one phase (the GPU default) as a light first_pass without the exact path and a retry
// of the sites it hands on (star.comp's EXACT_PATH, RETRY), against one full pass: every
// triangle of the full pass, and no more deferrals. The retry also decides incircles from exact
// coordinate differences (EXACT_DIFFERENCES), which the full pass does not, so it may make
// triangles that the full pass defers; with as many deferrals, the same triangles. The exact
// path matters on `needs_exact` inputs (a lattice of binary fractions, whose cocircular cells
// the filters cannot decide but the exact path can): there a retry that did not run would leave
// the handed-on sites' triangles unmade.
void check_light_pass(const std::string& name, const std::vector<Point2>& points, bool needs_exact) {
  const detail::SiteSet sites = detail::prepare_sites(points);
  const detail::Hull hull = detail::convex_hull(sites);
  const Layout layout{};
  setenv("EXPANSE_VULKAN_PHASES", "1", 1);
  setenv("EXPANSE_VULKAN_LIGHT_PASS", "0", 1);
  const detail::GrowResult full = detail::make_vulkan_backend(-1)->grow({sites, hull, layout});
  unsetenv("EXPANSE_VULKAN_LIGHT_PASS");
  const detail::GrowResult light = detail::make_vulkan_backend(-1)->grow({sites, hull, layout});
  unsetenv("EXPANSE_VULKAN_PHASES");
  const std::vector<Triangle> full_triangles = canonical(full.partial.triangles);
  const std::vector<Triangle> light_triangles = canonical(light.partial.triangles);
  VK_CHECK_THAT(std::includes(light_triangles.begin(), light_triangles.end(), full_triangles.begin(),
                              full_triangles.end()),
                "%s: %zu triangles in one full pass, %zu in the light pass and its retry, not all of the first",
                name.c_str(), full.partial.triangles.size(), light.partial.triangles.size());
  VK_CHECK_THAT(light.partial.deferred_expansions <= full.partial.deferred_expansions,
                "%s: %zu deferred sites in one full pass, %zu in the light pass and its retry", name.c_str(),
                full.partial.deferred_expansions, light.partial.deferred_expansions);
  VK_CHECK_THAT(light.partial.deferred_expansions < full.partial.deferred_expansions || light_triangles == full_triangles,
                "%s: as many deferrals, other triangles (%zu against %zu)", name.c_str(),
                light.partial.triangles.size(), full.partial.triangles.size());
  if (needs_exact)  // most sites decided, many of them by the exact path
    VK_CHECK_THAT(full.partial.deferred_expansions * 10 < sites.size(), "%s: %zu of %zu sites deferred",
                  name.c_str(), full.partial.deferred_expansions, std::size_t(sites.size()));
  std::printf("  %-40s light pass and retry: triangles %7zu  deferred %5zu (one full pass: %zu, %zu)\n",
              name.c_str(), light.partial.triangles.size(), light.partial.deferred_expansions,
              full.partial.triangles.size(), full.partial.deferred_expansions);
}

// The site preparation on the device (prepare_sites.comp, radix_sort.comp) against the host's
// prepare_sites and convex_hull, then grown on the GPU path from the sites it left on the
// device: the same sites, input indices, representatives and hull, and the same triangles as
// grown from the host's preparation. Where a run of equal Morton codes is too long for the
// pairwise search (`long_runs`: the input has one), the device sorts by (code, x, y) and the
// order within a run may differ: the sites are then compared as a set, and checked to be in
// Morton order.
void check_preparation(const std::string& name, const std::vector<Point2>& points, bool long_runs) {
  const detail::SiteSet host = detail::prepare_sites(points);
  const detail::Hull host_hull = detail::convex_hull(host);
  const detail::InputScan scan = detail::scan_input(points);
  const detail::InputHull input_hull = detail::convex_hull_of_input(points, scan);
  setenv("EXPANSE_VULKAN_PREPARE", "device", 1);
  setenv("EXPANSE_VULKAN_STAGED", "1", 1);
  setenv("EXPANSE_VULKAN_BUCKET", "device", 1);
  const Layout layout{};
  auto backend = detail::make_vulkan_backend(-1);
  std::optional<detail::InputGrowResult> device =
      backend->grow_from_input({points, scan, [&] { return &input_hull.sites; }, layout});
  const detail::GrowResult from_host = backend->grow({host, host_hull, layout});
  unsetenv("EXPANSE_VULKAN_PREPARE");
  unsetenv("EXPANSE_VULKAN_STAGED");
  unsetenv("EXPANSE_VULKAN_BUCKET");
  VK_CHECK_THAT(device.has_value(), "%s: the device declined", name.c_str());
  if (!device) return;
  const detail::SiteSet& sites = device->sites;
  VK_CHECK_THAT(sites.points.size() == host.points.size(), "%s: %zu sites on the device, %zu on the host",
                name.c_str(), sites.points.size(), host.points.size());
  if (sites.points.size() != host.points.size()) return;
  VK_CHECK_THAT(sites.representative == host.representative, "%s: representatives differ", name.c_str());
  VK_CHECK_THAT(sites.scale_exponent == host.scale_exponent, "%s: scale differs", name.c_str());
  const std::size_t m = sites.points.size();
  const bool same_order = std::equal(sites.points.begin(), sites.points.end(), host.points.begin(),
                                     [](const Point2& a, const Point2& b) { return a.x == b.x && a.y == b.y; }) &&
                          std::equal(sites.input_index.begin(), sites.input_index.end(), host.input_index.begin());
  // The path taken, where the queue has timestamps to name it.
  const auto& timed = device->grown.device_stages;
  if (!timed.empty()) {
    const bool sorted_again = std::any_of(timed.begin(), timed.end(), [](const StageTime& s) {
      return s.name == "vulkan: prepare (sort by point)";
    });
    VK_CHECK_THAT(sorted_again == long_runs, "%s: sorted again by point %d, expected %d", name.c_str(),
                  int(sorted_again), int(long_runs));
  }
  if (!long_runs) {
    VK_CHECK_THAT(same_order, "%s: the sites or their order differ from prepare_sites'", name.c_str());
  } else {
    const detail::Quantiser q(host.bounds);
    bool in_order = true;
    for (std::size_t k = 1; k < m; ++k)
      in_order &= detail::morton_code(q.x(sites.points[k - 1].x), q.y(sites.points[k - 1].y)) <=
                  detail::morton_code(q.x(sites.points[k].x), q.y(sites.points[k].y));
    VK_CHECK_THAT(in_order, "%s: the sites are not in Morton order", name.c_str());
    auto as_set = [](const detail::SiteSet& s) {
      std::vector<std::tuple<double, double, std::int32_t>> v;
      for (std::size_t k = 0; k < s.points.size(); ++k) v.emplace_back(s.points[k].x, s.points[k].y, s.input_index[k]);
      std::sort(v.begin(), v.end());
      return v;
    };
    VK_CHECK_THAT(as_set(sites) == as_set(host), "%s: the sites differ from prepare_sites'", name.c_str());
  }
  // The hull: the same points in the same order, and its predecessors.
  bool hull_same = device->hull.sites.size() == host_hull.sites.size();
  for (std::size_t k = 0; hull_same && k < host_hull.sites.size(); ++k)
    hull_same = sites.input_index[std::size_t(device->hull.sites[k])] == host.input_index[std::size_t(host_hull.sites[k])];
  VK_CHECK_THAT(hull_same, "%s: the hull differs from convex_hull's", name.c_str());
  std::size_t on_hull = 0;
  for (std::size_t k = 0; k < m; ++k) on_hull += device->hull.predecessor[k] >= 0;
  VK_CHECK_THAT(on_hull == device->hull.sites.size(), "%s: %zu sites have a hull predecessor, %zu on the hull",
                name.c_str(), on_hull, device->hull.sites.size());
  // The growth from the device's sites: the same triangles, in input indices.
  auto in_input = [](const detail::PartialTriangulation& partial, const detail::SiteSet& s) {
    std::vector<Triangle> t = partial.triangles;
    for (Triangle& tri : t)
      for (auto& v : tri) v = s.input_index[std::size_t(v)];
    return canonical(std::move(t));
  };
  VK_CHECK_THAT(in_input(device->grown.partial, sites) == in_input(from_host.partial, host),
                "%s: %zu triangles grown from the device's sites, %zu from the host's, or others", name.c_str(),
                device->grown.partial.triangles.size(), from_host.partial.triangles.size());
  VK_CHECK_THAT(!has_stage(device->grown, "vulkan: stage"), "%s: the sites were uploaded again", name.c_str());
  std::printf("  %-40s %7zu sites  %s  triangles %7zu  deferred %5zu\n", name.c_str(), m,
              long_runs ? "sorted again by point" : "Morton order = host's", device->grown.partial.triangles.size(),
              device->grown.partial.deferred_expansions);
}

// A CPU triangulation as a partial one in SiteSet ids, with its adjacency.
struct Reference {
  detail::SiteSet sites;
  detail::Hull hull;
  detail::PartialTriangulation partial;
};

Reference reference(const std::vector<Point2>& points) {
  Reference r{detail::prepare_sites(points), {}, {}};
  r.hull = detail::convex_hull(r.sites);
  Options cpu;
  cpu.backend = BackendKind::cpu;
  const Mesh mesh = triangulate(points, cpu);
  std::vector<std::int32_t> site_of(points.size(), -1);
  for (std::size_t s = 0; s < r.sites.input_index.size(); ++s)
    site_of[std::size_t(r.sites.input_index[s])] = std::int32_t(s);
  for (const Triangle& t : mesh.triangles)
    r.partial.triangles.push_back({site_of[std::size_t(t[0])], site_of[std::size_t(t[1])],
                                   site_of[std::size_t(t[2])]});
  r.partial.neighbors = mesh.neighbors;
  return r;
}

// Slot k of triangle t whose neighbour is `u`, or -1.
int slot_towards(const detail::PartialTriangulation& p, std::size_t t, std::int32_t u) {
  for (int k = 0; k < 3; ++k)
    if (p.neighbors[t][std::size_t(k)] == u) return k;
  return -1;
}

// The staging ring with tiny slots: pieces of odd sizes that straddle chunks and share them,
// up to the device and back, byte for byte; more chunks than slots, so slots are reused while
// others are in flight.
void check_staging_ring() {
  auto context = detail::vk::shared_context(-1);
  std::lock_guard lock(context->mutex());
  std::mt19937_64 rng(5);
  for (VkDeviceSize chunk : {VkDeviceSize(64), VkDeviceSize(4096), VkDeviceSize(1) << 20}) {
    detail::vk::StagingRing ring(*context, chunk, 3);
    const std::size_t sizes[] = {1, 7, 4096, 100003, 3 * 4096 + 5, 0, 250000};
    std::vector<std::vector<unsigned char>> in, out;
    std::vector<std::unique_ptr<detail::vk::Buffer>> buffers;
    std::vector<detail::vk::StagingRing::Upload> up;
    std::vector<detail::vk::StagingRing::Download> down;
    for (std::size_t size : sizes) {
      in.emplace_back(size);
      for (auto& b : in.back()) b = static_cast<unsigned char>(rng());
      out.emplace_back(size, 0);
      // At an offset inside the buffer, so that offsets are checked too.
      buffers.push_back(std::make_unique<detail::vk::Buffer>(*context, size + 12, false));
      up.push_back({in.back().data(), buffers.back()->handle(), 12, size});
      down.push_back({buffers.back()->handle(), 12, out.back().data(), size});
    }
    ring.upload(up);
    ring.download(down);
    bool same = true;
    for (std::size_t i = 0; i < in.size(); ++i) same = same && in[i] == out[i];
    VK_CHECK_THAT(same, "staging ring, %llu-byte chunks: the round trip changed the bytes",
                  static_cast<unsigned long long>(chunk));
  }
  std::printf("  staging ring: round trips through 64 B, 4 KiB and 1 MiB slots\n");
}

// The free function makes a Backend per call; on the process-wide context the second call of
// the same size must make no buffer (the context's cache and staging ring are reused), on
// both paths. EXPANSE_VULKAN_KEEP_MB=0 releases them after every call.
void check_buffers_kept() {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Point2> p(70000);
  for (auto& q : p) q = {unit(rng), unit(rng)};
  Options vk;
  vk.backend = BackendKind::vulkan;
  for (const char* staged : {"0", "1"}) {
    setenv("EXPANSE_VULKAN_STAGED", staged, 1);
    setenv("EXPANSE_VULKAN_BUCKET", "device", 1);
    const auto first = triangulate(p, vk);
    const std::uint64_t before = detail::vk::Buffer::made();
    const auto second = triangulate(p, vk);
    const std::uint64_t made = detail::vk::Buffer::made() - before;
    VK_CHECK_THAT(made == 0, "staged=%s: a second call of the same size made %llu buffers", staged,
                  static_cast<unsigned long long>(made));
    VK_CHECK_THAT(canonical(first.triangles) == canonical(second.triangles),
                  "staged=%s: the second call's triangles differ", staged);
    setenv("EXPANSE_VULKAN_KEEP_MB", "0", 1);
    const auto third = triangulate(p, vk);
    VK_CHECK_THAT(detail::vk::shared_context(-1)->buffers().bytes() == 0,
                  "staged=%s: EXPANSE_VULKAN_KEEP_MB=0 kept buffers", staged);
    VK_CHECK_THAT(canonical(first.triangles) == canonical(third.triangles),
                  "staged=%s: the triangles differ with nothing kept", staged);
    unsetenv("EXPANSE_VULKAN_KEEP_MB");
    std::printf("  kept buffers, staged=%s: a second call made %llu buffers\n", staged,
                static_cast<unsigned long long>(made));
  }
  unsetenv("EXPANSE_VULKAN_STAGED");
  unsetenv("EXPANSE_VULKAN_BUCKET");
}

}  // namespace

void test_device_passes() {
  check_staging_ring();
  check_buffers_kept();
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> normal(0.0, 1.0);
  {
    // Preparation: the radix sort's tiles (2048 with 256-invocation workgroups) and its scans at
    // three levels; duplicates in short runs; long runs (copies of one point, a cluster finer
    // than the quantisation, +0 and -0); the scale past 2^1023; integers.
    std::vector<Point2> p(300000);
    for (auto& q : p) q = {unit(rng), unit(rng)};
    check_preparation("uniform 300000", p, false);
    std::vector<Point2> d;
    for (int k = 0; k < 40000; ++k) d.push_back(p[std::size_t(k) % 9000]);
    check_preparation("40000, 9000 distinct, interleaved", d, false);
    std::vector<Point2> c(p.begin(), p.begin() + 20000);
    for (int k = 0; k < 500; ++k) c.insert(c.begin() + 37 * k, p[5]);
    for (int k = 0; k < 300; ++k) c.push_back({0.25 + 1e-12 * unit(rng), 0.75 + 1e-12 * unit(rng)});
    for (int k = 0; k < 200; ++k) c.push_back({k % 2 ? -0.0 : 0.0, 0.5});
    check_preparation("long runs of one code", c, true);
    std::vector<Point2> tiny(20000);
    for (auto& q : tiny) q = {std::ldexp(unit(rng), -1060), std::ldexp(unit(rng), -1060)};
    check_preparation("subnormal 20000", tiny, false);
    std::vector<Point2> g;
    for (int x = 0; x < 200; ++x)
      for (int y = 0; y < 200; ++y) g.push_back({double(x) - 100.0, double(y) * 3.0});
    std::shuffle(g.begin(), g.end(), rng);
    check_preparation("grid 200x200, shuffled", g, false);
    std::vector<Point2> gauss(50000);
    for (auto& q : gauss) q = {1e6 + normal(rng), -1e6 + normal(rng)};
    check_preparation("gaussian 50000 off the origin", gauss, false);
    // One cell too crowded for the device's bucketing: the host buckets, after the sites' copy.
    std::vector<Point2> crowded;
    for (int k = 0; k < 5000; ++k) crowded.push_back({0.5 + 1e-9 * unit(rng), 0.5 + 1e-9 * unit(rng)});
    for (const Point2 corner : {Point2{0.0, 0.0}, Point2{1.0, 0.1}, Point2{0.2, 1.0}}) crowded.push_back(corner);
    check_preparation("5000 in one cell + 3", crowded, true);
  }
  {
    // Grids from one (crowded) cell to more cells than sites; the largest scans three levels
    // of tiles (1024 per tile with 256-invocation workgroups).
    std::vector<Point2> p(200000);
    for (auto& q : p) q = {unit(rng), unit(rng)};
    for (int cells : {1, 10, 316, 1500}) check_bucketing("uniform 200000", p, cells);
    std::vector<Point2> g(30000);
    for (auto& q : g) q = {normal(rng), normal(rng)};
    for (int cells : {3, 20, 200}) check_bucketing("gaussian 30000", g, cells);
  }
  {
    std::vector<Point2> p(70000);
    for (auto& q : p) q = {unit(rng), unit(rng)};
    check_same_output("uniform 70000", p, false);
    check_light_pass("uniform 70000", p, false);
    // Not integers, so the light pass takes it (integer inputs off the small lattices do not).
    std::vector<Point2> g;
    for (int x = 0; x < 120; ++x)
      for (int y = 0; y < 120; ++y) g.push_back({0.375 * x, 0.375 * y});
    check_light_pass("grid 120x120, 3/8 apart", g, true);
  }
  {
    std::vector<Point2> p(40000);
    for (auto& q : p) q = {normal(rng), normal(rng)};
    check_same_output("gaussian 40000", p, false);
  }
  {
    std::vector<Point2> p;
    for (int x = 0; x < 150; ++x)
      for (int y = 0; y < 150; ++y) p.push_back({double(x), double(y)});
    check_same_output("grid 150x150 (cocircular)", p, false);
  }
  {
    // A kuzmin disc (mass within r: 1 - 1 / sqrt(1 + r^2)): uniform cells would crowd its centre,
    // so the grid has quantile cells (star_cells.cpp), looked up alike by bucket.comp and the host.
    std::vector<Point2> p(60000);
    for (auto& q : p) {
      const double u = 0.999999 * unit(rng), r = std::sqrt(1.0 / ((1.0 - u) * (1.0 - u)) - 1.0);
      const double a = 6.283185307179586 * unit(rng);
      q = {r * std::cos(a), r * std::sin(a)};
    }
    check_same_output("kuzmin 60000 (quantile cells)", p, false);
  }
  {
    // 5000 sites within 1e-9 of one point and three far away: the grid is sized by the
    // typical site's density but capped at 16 cells per site, so one cell holds the cluster.
    std::vector<Point2> p;
    for (int k = 0; k < 5000; ++k) p.push_back({0.5 + 1e-9 * unit(rng), 0.5 + 1e-9 * unit(rng)});
    p.push_back({0.0, 0.0});
    p.push_back({1.0, 0.1});
    p.push_back({0.2, 1.0});
    check_same_output("5000 in one cell + 3 (host fallback)", p, true);
  }

  // The device audit on a correct adjacency, on a partial one (triangles left to the seam), and
  // on three ways of breaking it.
  std::vector<Point2> points(5000);
  for (auto& q : points) q = {unit(rng), unit(rng)};
  const Reference ref = reference(points);
  auto context = detail::vk::shared_context(-1);
  const auto& tris = ref.partial.triangles;
  VK_CHECK_THAT(detail::adjacency_is_trustworthy(ref.partial, ref.hull), "reference adjacency");
  VK_CHECK_THAT(detail::vk::audit_on_device(*context, ref.partial, ref.hull),
                "the device audit rejects a correct adjacency");
  {
    detail::PartialTriangulation partial = ref.partial;  // the last 20 triangles left to the seam
    const std::int32_t kept = std::int32_t(tris.size() - 20);
    partial.triangles.resize(std::size_t(kept));
    partial.neighbors.resize(std::size_t(kept));
    for (auto& row : partial.neighbors)
      for (auto& u : row)
        if (u >= kept) u = no_neighbor;
    VK_CHECK_THAT(detail::vk::audit_on_device(*context, partial, ref.hull),
                  "the device audit rejects a partial triangulation's adjacency");
  }
  // An interior triangle and one of its neighbours.
  std::size_t t = 0;
  while (std::count(ref.partial.neighbors[t].begin(), ref.partial.neighbors[t].end(), no_neighbor) > 0) ++t;
  const std::int32_t u = ref.partial.neighbors[t][0];
  {
    detail::PartialTriangulation broken = ref.partial;  // a link to the wrong triangle
    broken.neighbors[t][0] = ref.partial.neighbors[t][1];
    VK_CHECK_THAT(!detail::vk::audit_on_device(*context, broken, ref.hull),
                  "the device audit passes a link to the wrong triangle");
  }
  {
    detail::PartialTriangulation broken = ref.partial;  // one side of an edge unlinked
    broken.neighbors[t][0] = no_neighbor;
    VK_CHECK_THAT(!detail::vk::audit_on_device(*context, broken, ref.hull),
                  "the device audit passes a one-sided link");
  }
  {
    detail::PartialTriangulation broken = ref.partial;  // an edge marked open from both sides
    broken.neighbors[t][0] = no_neighbor;
    broken.neighbors[std::size_t(u)][std::size_t(slot_towards(ref.partial, std::size_t(u), std::int32_t(t)))] =
        no_neighbor;
    VK_CHECK_THAT(!detail::vk::audit_on_device(*context, broken, ref.hull),
                  "the device audit passes an edge open on both sides with triangles across");
    VK_CHECK_THAT(!detail::adjacency_is_trustworthy(broken, ref.hull), "host audit, same case");
  }
  std::printf("  device audit: correct, partial and three broken adjacencies judged as the host's\n");
}

}  // namespace expanse::vulkan_tests
