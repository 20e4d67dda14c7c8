// Backend smoke tests: the Vulkan backend (both layouts) must give exactly the CPU backend's
// triangles on small inputs of every awkward kind, and must make most of them on the device.
#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "backends/backend.hpp"
#include "expanse/triangulate.hpp"
#include "harness.hpp"
#include "hull/convex_hull.hpp"
#include "input/site_set.hpp"
#include "seam/adjacency_audit.hpp"

namespace expanse::vulkan_tests {
namespace {

struct Input {
  std::string name;
  std::vector<Point2> points;
  bool expect_mostly_gpu;
};

std::vector<Input> inputs() {
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<Input> in;
  {
    Input i{"uniform 3000", {}, true};
    for (int k = 0; k < 3000; ++k) i.points.push_back({unit(rng), unit(rng)});
    in.push_back(i);
  }
  {
    Input i{"gaussian 3000", {}, true};
    for (int k = 0; k < 3000; ++k) i.points.push_back({normal(rng), normal(rng)});
    in.push_back(i);
  }
  {
    Input i{"grid 40x40 (cocircular everywhere)", {}, true};
    for (int x = 0; x < 40; ++x)
      for (int y = 0; y < 40; ++y) i.points.push_back({double(x), double(y)});
    in.push_back(i);
  }
  {
    Input i{"circle 200 + centre (star overflow)", {}, false};
    for (int k = 0; k < 200; ++k)
      i.points.push_back({std::cos(k * 0.0314159), std::sin(k * 0.0314159)});
    i.points.push_back({0, 0});
    in.push_back(i);
  }
  {
    Input i{"duplicates and collinear hull", {}, true};
    for (int k = 0; k <= 20; ++k) {
      i.points.push_back({double(k), 0});
      i.points.push_back({double(k), 20});
      i.points.push_back({0, double(k)});
      i.points.push_back({20, double(k)});
    }
    for (int k = 0; k < 300; ++k) i.points.push_back({1 + 18 * unit(rng), 1 + 18 * unit(rng)});
    in.push_back(i);
  }
  {
    Input i{"three points", {{0, 0}, {1, 0}, {0, 1}}, true};
    in.push_back(i);
  }
  {
    // Wheels of 96 rim sites around two hub sites: both hubs exceed the device's star capacity
    // and defer, and they are adjacent, so the triangles across the hub-hub edge (owned by rim
    // sites) can only be linked through the backend's unresolved-slot pairing.
    Input i{"wheels with two adjacent deferred hubs", {}, false};
    for (int wy = 0; wy < 6; ++wy)
      for (int wx = 0; wx < 6; ++wx) {
        const double cx = 10.0 * wx, cy = 10.0 * wy, turn = 0.1 * (wx + 6 * wy);
        for (int k = 0; k < 96; ++k) {
          // Radii jittered: cocircular rims would defer on inexact predicates instead.
          const double a = turn + k * (2 * M_PI / 96), r = 4 + 0.2 * unit(rng);
          i.points.push_back({cx + r * std::cos(a), cy + r * std::sin(a)});
        }
        // Hub pairs in varied directions, so that in some wheels both rim sites across the
        // hub-hub edge come first in site order and both triangles there are emitted.
        const double h = 0.37 * (wx + 6 * wy);
        i.points.push_back({cx - 0.1 * std::cos(h), cy - 0.1 * std::sin(h)});
        i.points.push_back({cx + 0.1 * std::cos(h), cy + 0.1 * std::sin(h)});
      }
    in.push_back(i);
  }
  return in;
}

// The backend's own adjacency, checked exactly (not through the audit's hashes) and by the audit
// the pipeline uses: every link crosses a shared edge and is symmetric, and a slot is
// no_neighbor exactly when no emitted triangle lies across the edge.
void check_device_adjacency(const Input& input) {
  const detail::SiteSet sites = detail::prepare_sites(input.points);
  const detail::Hull hull = detail::convex_hull(sites);
  const Layout layout{};
  auto backend = detail::make_vulkan_backend(-1);
  const detail::GrowResult grown = backend->grow({sites, hull, layout});
  const detail::PartialTriangulation& partial = grown.partial;
  const auto& tris = partial.triangles;
  const auto& nbrs = partial.neighbors;
  VK_CHECK_THAT(nbrs.size() == tris.size(), "%s: %zu neighbour rows for %zu triangles",
                input.name.c_str(), nbrs.size(), tris.size());
  if (nbrs.size() != tris.size()) return;
  VK_CHECK_THAT(detail::adjacency_is_trustworthy(partial, hull),
                "%s: the device adjacency fails the pipeline's audit", input.name.c_str());
  std::map<std::pair<std::int32_t, std::int32_t>, std::int32_t> edge_owner;  // directed edge -> t
  for (std::size_t t = 0; t < tris.size(); ++t)
    for (int k = 0; k < 3; ++k) edge_owner[{tris[t][(k + 1) % 3], tris[t][(k + 2) % 3]}] = std::int32_t(t);
  std::size_t wrong = 0, links = 0;
  for (std::size_t t = 0; t < tris.size(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const std::int32_t x = tris[t][(k + 1) % 3], y = tris[t][(k + 2) % 3];
      const auto across = edge_owner.find({y, x});
      const std::int32_t expected = across == edge_owner.end() ? no_neighbor : across->second;
      const std::int32_t u = nbrs[t][k];
      if (u != no_neighbor) ++links;
      bool ok = u == expected;
      if (ok && u != no_neighbor) {
        // The link crosses a shared edge, and the neighbour links back through that edge.
        const Triangle& other = tris[std::size_t(u)];
        bool back = false;
        for (int j = 0; j < 3; ++j)
          back = back || (other[(j + 1) % 3] == y && other[(j + 2) % 3] == x && nbrs[std::size_t(u)][j] == std::int32_t(t));
        ok = back;
      }
      if (!ok && wrong++ < 5)
        VK_CHECK_THAT(ok, "%s: triangle %zu slot %d links %d, expected %d", input.name.c_str(), t, k, u,
                      expected);
    }
  }
  VK_CHECK_THAT(wrong == 0, "%s: %zu wrong adjacency slots", input.name.c_str(), wrong);
  std::printf("  %-40s device adjacency: %zu triangles, %zu links, %zu deferred sites\n",
              input.name.c_str(), tris.size(), links, partial.deferred_expansions);
}

// Exactly the CPU backend's triangles, through the pipeline; and the backend's own adjacency
// (before the pipeline) consistent with its triangles: every link crosses a shared edge and
// links back, and a slot is no_neighbor exactly when no emitted triangle lies across.
void check_large(const std::string& name, const std::vector<Point2>& points,
                 const std::vector<Triangle>& expected, bool staged, bool device_bucketing) {
  setenv("EXPANSE_VULKAN_STAGED", staged ? "1" : "0", 1);
  setenv("EXPANSE_VULKAN_BUCKET", device_bucketing ? "device" : "host", 1);
  const char* path = staged ? (device_bucketing ? "staged, bucketed on the device" : "staged")
                            : (device_bucketing ? "in place, bucketed on the device" : "in place");
  Options vk;
  vk.backend = BackendKind::vulkan;
  const Mesh mesh = triangulate(points, vk);
  VK_CHECK_THAT(canonical(mesh.triangles) == expected, "%s, %s: %zu triangles, CPU %zu",
                name.c_str(), path, mesh.triangles.size(), expected.size());
  VK_CHECK_THAT(mesh.stats.gpu_triangles * 100 >= mesh.triangles.size() * 99,
                "%s, %s: only %zu of %zu triangles made on the device", name.c_str(), path,
                mesh.stats.gpu_triangles, mesh.triangles.size());

  const detail::SiteSet sites = detail::prepare_sites(points);
  const detail::Hull hull = detail::convex_hull(sites);
  const Layout layout{};
  const detail::GrowResult grown = detail::make_vulkan_backend(-1)->grow({sites, hull, layout});
  const auto& tris = grown.partial.triangles;
  const auto& nbrs = grown.partial.neighbors;
  VK_CHECK_THAT(nbrs.size() == tris.size(), "%s, %s: %zu neighbour rows for %zu triangles",
                name.c_str(), path, nbrs.size(), tris.size());
  if (nbrs.size() != tris.size()) return;
  auto key = [](std::int32_t x, std::int32_t y) { return (std::uint64_t(std::uint32_t(x)) << 32) | std::uint32_t(y); };
  std::unordered_map<std::uint64_t, std::int32_t> edge_owner;  // directed edge -> triangle
  edge_owner.reserve(3 * tris.size());
  for (std::size_t t = 0; t < tris.size(); ++t)
    for (int k = 0; k < 3; ++k) edge_owner[key(tris[t][(k + 1) % 3], tris[t][(k + 2) % 3])] = std::int32_t(t);
  std::size_t wrong = 0;
  for (std::size_t t = 0; t < tris.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const auto across = edge_owner.find(key(tris[t][(k + 2) % 3], tris[t][(k + 1) % 3]));
      const std::int32_t want = across == edge_owner.end() ? no_neighbor : across->second;
      if (nbrs[t][k] != want && wrong++ < 3)
        VK_CHECK_THAT(false, "%s, %s: triangle %zu slot %d links %d, expected %d", name.c_str(), path,
                      t, k, nbrs[t][k], want);
    }
  VK_CHECK_THAT(wrong == 0, "%s, %s: %zu wrong adjacency slots", name.c_str(), path, wrong);
  std::printf("  %-44s %-32s triangles %7zu  gpu %7zu  seam %5zu  deferred %4zu\n", name.c_str(),
              path, mesh.triangles.size(), mesh.stats.gpu_triangles, mesh.stats.seam_triangles,
              mesh.stats.deferred_expansions);
}

}  // namespace

// The per-site layout where its host passes run on all threads (>= 65536 sites), where the grid
// is sized by crowding (clusters), and past lavapipe's dispatch split (65535 workgroups of 8
// sites), on both paths: in place (CPU devices) and staged (GPUs: copies, star_links.comp),
// and the staged one also with the GPUs' bucketing and audit on the device.
void test_stars() {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<std::pair<std::string, std::vector<Point2>>> cases;
  {
    std::vector<Point2> p(100000);
    for (auto& q : p) q = {unit(rng), unit(rng)};
    cases.emplace_back("uniform 100000", std::move(p));
  }
  {
    std::vector<Point2> p(100000);
    for (auto& q : p) q = {normal(rng), normal(rng)};
    cases.emplace_back("gaussian 100000", std::move(p));
  }
  {
    // Two clusters far apart and a few sites between: the grid is sized by the clusters'
    // density (the crowding factor reaches its cap), not by the mean over the empty box.
    std::vector<Point2> p;
    for (int k = 0; k < 30000; ++k) p.push_back({normal(rng), normal(rng)});
    for (int k = 0; k < 30000; ++k) p.push_back({100 + normal(rng), 50 + normal(rng)});
    for (int k = 0; k < 200; ++k) p.push_back({100 * unit(rng), 50 * unit(rng)});
    cases.emplace_back("two clusters 60000 + 200 between", std::move(p));
  }
  {
    std::vector<Point2> p(530000);
    for (auto& q : p) q = {unit(rng), unit(rng)};
    cases.emplace_back("uniform 530000 (two dispatches on lavapipe)", std::move(p));
  }
  for (const auto& [name, points] : cases) {
    Options cpu;
    cpu.backend = BackendKind::cpu;
    const auto expected = canonical(triangulate(points, cpu).triangles);
    // The GPU path as a GPU takes it: staged, bucketed on the device (past the dispatch split
    // too: its passes cover up to 6 invocations per site).
    for (bool staged : {false, true}) check_large(name, points, expected, staged, false);
    check_large(name, points, expected, true, true);
  }
  unsetenv("EXPANSE_VULKAN_STAGED");
  unsetenv("EXPANSE_VULKAN_BUCKET");
}

void test_backend() {
  for (const Input& input : inputs()) check_device_adjacency(input);
  Layout paper = Layout::paper();
  paper.blocks_per_side = 4;
  paper.buckets_per_block_side = 4;
  Layout dense_paper = Layout::paper();  // the real 16x16 blocks of 16x16 buckets
  const std::pair<const char*, Layout> layouts[] = {
      {"per-site", Layout{}}, {"paper 4x4", paper}, {"paper 16x16", dense_paper}};
  for (const Input& input : inputs()) {
    Options cpu;
    cpu.backend = BackendKind::cpu;
    const Mesh reference = triangulate(input.points, cpu);
    const auto expected = canonical(reference.triangles);
    for (const auto& [layout_name, layout] : layouts) {
      Options vk;
      vk.backend = BackendKind::vulkan;
      vk.layout = layout;
      const Mesh mesh = triangulate(input.points, vk);
      const bool same = canonical(mesh.triangles) == expected;
      VK_CHECK_THAT(same, "%s, %s: %zu triangles, CPU %zu", input.name.c_str(), layout_name,
                    mesh.triangles.size(), expected.size());
      VK_CHECK_THAT(mesh.stats.gpu_triangles + mesh.stats.seam_triangles == mesh.triangles.size(),
                    "%s, %s: stats do not add up", input.name.c_str(), layout_name);
      std::printf("  %-40s %-12s triangles %7zu  gpu %7zu  seam %6zu  deferred %5zu  iterations %zu\n",
                  input.name.c_str(), layout_name, mesh.triangles.size(), mesh.stats.gpu_triangles,
                  mesh.stats.seam_triangles, mesh.stats.deferred_expansions, mesh.stats.iterations);
      if (input.expect_mostly_gpu && std::string(layout_name) == "per-site")
        VK_CHECK_THAT(mesh.stats.gpu_triangles * 10 >= mesh.triangles.size() * 9,
                      "%s: only %zu of %zu triangles made on the device", input.name.c_str(),
                      mesh.stats.gpu_triangles, mesh.triangles.size());
    }
  }
}

}  // namespace expanse::vulkan_tests
