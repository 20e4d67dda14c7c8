// Where the input is prepared: a backend may sort and merge the raw points on its device
// (Backend::grow_from_input; the CUDA backend does) instead of the host's prepare_sites. Both
// must give CGAL's mesh, and the device must take the inputs it is meant to take.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

#include "conformance.hpp"
#include "expanse/triangulate.hpp"
#include "support/test_points.hpp"

using namespace expanse;
using namespace expanse::conformance;

namespace {

bool has_stage(const Mesh& mesh, const std::string& name) {
  return std::any_of(mesh.stats.stages.begin(), mesh.stats.stages.end(),
                     [&](const StageTime& s) { return s.name == name; });
}

/// Sets EXPANSE_CUDA_PREPARE=host and EXPANSE_VULKAN_PREPARE=host for its lifetime.
struct HostPreparation {
  HostPreparation() {
    if (const char* vulkan = std::getenv("EXPANSE_VULKAN_PREPARE")) vulkan_before = vulkan;
    setenv("EXPANSE_CUDA_PREPARE", "host", 1);
    setenv("EXPANSE_VULKAN_PREPARE", "host", 1);
  }
  ~HostPreparation() {
    unsetenv("EXPANSE_CUDA_PREPARE");
    if (vulkan_before.empty())
      unsetenv("EXPANSE_VULKAN_PREPARE");
    else
      setenv("EXPANSE_VULKAN_PREPARE", vulkan_before.c_str(), 1);
  }
  std::string vulkan_before;
};

/// Whether the backend under test is meant to prepare on its device: CUDA always; Vulkan on
/// GPUs, and on lavapipe (a CPU device, which prepares on the host by default) where
/// EXPANSE_VULKAN_PREPARE=device asks it to (as CI does).
bool device_prepares(const Mesh& mesh) {
  if (backend_under_test() == BackendKind::cuda) return true;
  if (backend_under_test() != BackendKind::vulkan) return false;
  if (const char* where = std::getenv("EXPANSE_VULKAN_PREPARE")) return std::string(where) == "device";
  return mesh.stats.device.find("llvmpipe") == std::string::npos;
}

std::vector<Point2> crowded_copies(std::size_t n, std::uint64_t seed) {
  // Uniform points, and 300 copies of one of them (interleaved): one run of equal codes.
  std::vector<Point2> points = test::points::uniform(n, seed);
  const Point2 repeated = points[n / 2];
  for (std::size_t k = 0; k < 300; ++k) points.insert(points.begin() + static_cast<std::ptrdiff_t>(k * (n / 300)), repeated);
  return points;
}

std::vector<Point2> subnormal(std::size_t n, std::uint64_t seed) {
  // Uniform points times 2^-1060, below the smallest normal double: scaling them into [0.5, 1)
  // takes more than 2^1023 (ldexp on the host, scalbn on a device).
  std::vector<Point2> points = test::points::uniform(n, seed);
  for (Point2& p : points) p = {std::ldexp(p.x, -1060), std::ldexp(p.y, -1060)};
  return points;
}

std::vector<Point2> copied_hull(std::size_t n, std::uint64_t seed) {
  // Integer points in a square with its boundary filled in, every boundary point repeated
  // three times after the first: the hull's collinear sites each name their first copy.
  std::vector<Point2> points = test::points::square_boundary(n / 2, seed);
  const std::size_t boundary = points.size();
  const std::vector<Point2> inside = test::points::uniform(n / 2, seed + 1);
  double extent = 0.0;
  for (const Point2& p : points) extent = std::max({extent, p.x, p.y});
  for (const Point2& p : inside) points.push_back({1.0 + p.x * (extent - 2.0), 1.0 + p.y * (extent - 2.0)});
  for (int copy = 0; copy < 3; ++copy)
    for (std::size_t k = 0; k < boundary; ++k) points.push_back(points[k]);
  return points;
}

std::vector<Point2> signed_zeros(std::size_t n, std::uint64_t seed) {
  // Uniform points, and 200 copies each of two points on the box's edges written with +0 and
  // -0 in turn: equal points whose bits differ, in runs long enough for the device's second sort.
  std::vector<Point2> points = test::points::uniform(n, seed);
  for (int k = 0; k < 200; ++k) {
    points.push_back({k % 2 ? -0.0 : 0.0, 0.25});
    points.push_back({0.5, k % 3 ? -0.0 : 0.0});
  }
  return points;
}

}  // namespace

TEST_CASE("prepared on the device or on the host: the same mesh, CGAL's", "[prepare]") {
  struct Case {
    const char* name;
    std::vector<Point2> points;
  };
  const std::vector<Case> cases = {
      {"uniform", test::points::uniform(30000, 1)},
      {"duplicates", test::points::duplicates(20000, 2)},
      {"kuzmin", test::points::kuzmin(30000, 3)},
      {"grid with duplicates", test::points::grid_with_duplicates(20000, 4)},
      {"tiny", test::points::tiny(5000, 5)},
      {"huge", test::points::huge(5000, 6)},
      {"tiny grid", test::points::tiny_grid(4000, 7)},
      // A cluster 1e-400 of the box wide: all of it one Morton code. (Kept small: every
      // predicate among its points underflows to the exact path, and the seam stage takes
      // minutes at 3000 points.)
      {"mixed scale", test::points::mixed_scale(300, 8)},
      {"subnormal", subnormal(3000, 11)},
      {"copied hull", copied_hull(4000, 9)},
      {"signed zeros", signed_zeros(5000, 12)},
      {"crowded copies", crowded_copies(20000, 10)},
      {"three points", {{0.0, 0.0}, {1.0, 0.0}, {0.0, 1.0}}},
  };
  Triangulator triangulator(options());
  for (const Case& c : cases) {
    INFO(c.name << ": " << c.points.size() << " points");
    const Mesh mesh = triangulator.triangulate(c.points);
    CHECK(differences_from_cgal(c.points, mesh, options()) == "");
    Mesh on_host;
    {
      const HostPreparation host;
      on_host = triangulator.triangulate(c.points);
    }
    CHECK(differences_from_cgal(c.points, on_host, options()) == "");
    CHECK(mesh.hull == on_host.hull);
    CHECK(mesh.representative == on_host.representative);
    CHECK(mesh.stats.sites == on_host.stats.sites);
    CHECK_FALSE(has_stage(on_host, "prepare (scan)"));
    if (device_prepares(mesh)) {
      // The device prepared it: the host only scanned. (Long runs of equal codes, the crowded
      // copies, the signed zeros and the mixed scale's cluster, take the device's second sort.)
      CHECK(has_stage(mesh, "prepare (scan)"));
      CHECK_FALSE(has_stage(mesh, "prepare"));
    } else {
      CHECK_FALSE(has_stage(mesh, "prepare (scan)"));
    }
  }
}
