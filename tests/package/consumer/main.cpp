// Triangulates a small set through the public API only; exits non-zero unless the mesh checks.
#include <expanse/expanse.hpp>

#include <cstdio>
#include <vector>

#ifdef CONSUMER_VULKAN_INTEROP
bool vulkan_interop_links();  // vulkan_interop.cpp
#endif

int main() {
  const std::vector<expanse::Point2> points{{0, 0}, {1, 0}, {0, 1}, {1, 1}, {0.5, 0.25}, {0.25, 0.75}};
  const expanse::Mesh mesh = expanse::triangulate(points, expanse::Options{expanse::BackendKind::cpu});
  bool ok = mesh.triangles.size() == 6 && expanse::check_mesh(points, mesh).ok;
#ifdef CONSUMER_VULKAN_INTEROP
  ok = ok && vulkan_interop_links();
#endif
  std::printf("consumer: %zu triangles, %s\n", mesh.triangles.size(), ok ? "ok" : "WRONG");
  return ok ? 0 : 1;
}
