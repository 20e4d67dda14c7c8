// Backend smoke tests: the Vulkan backend (both layouts) must give exactly the CPU backend's
// triangles on small inputs of every awkward kind, and must make most of them on the device.
#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "expanse/triangulate.hpp"
#include "harness.hpp"

namespace expanse::vulkan_tests {
namespace {

std::vector<Triangle> canonical(std::vector<Triangle> triangles) {
  for (Triangle& t : triangles) std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
  std::sort(triangles.begin(), triangles.end());
  return triangles;
}

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
  return in;
}

}  // namespace

void test_backend() {
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
