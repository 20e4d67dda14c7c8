#pragma once
// Where the front grows. A Backend hides only the device (memory, dispatch); the pipeline owns
// input preparation, seam completion and output conventions.
#include <memory>
#include <string>
#include <vector>

#include "expanse/mesh.hpp"
#include "expanse/options.hpp"
#include "expanse/triangulate.hpp"
#include "hull/convex_hull.hpp"
#include "input/site_set.hpp"
#include "seam/partial_triangulation.hpp"

namespace expanse::detail {

struct GrowInput {
  const SiteSet& sites;
  const Hull& hull;
  const Layout& layout;
  /// Vectors whose storage the backend may fill instead of allocating its own (the caller's
  /// previous mesh, Triangulator::triangulate(points, mesh)), or null: allocate_full_triangulation
  /// takes it.
  PartialTriangulation* recycled = nullptr;
};

struct GrowResult {
  PartialTriangulation partial;
  std::size_t iterations = 0;
  std::vector<StageTime> device_stages;  ///< device-timed stages (timestamps / events)
  std::vector<StageTime> host_stages;    ///< host-side stages inside the backend (upload, ...)
  /// The backend ran adjacency_is_trustworthy's checks where it made the adjacency and they
  /// passed (every link reciprocal; no open edge with a triangle across it): the pipeline's host
  /// audit is then skipped.
  bool adjacency_audited = false;
};

class Backend {
 public:
  virtual ~Backend() = default;
  virtual BackendKind kind() const = 0;
  virtual std::string device_name() const = 0;
  /// Grows the front as far as the device can decide exactly. Precondition: at least three
  /// sites, not all collinear.
  virtual GrowResult grow(const GrowInput& input) = 0;
};

/// The CPU backend grows nothing itself: the seam stage, seeded with one seed, does it all.
std::unique_ptr<Backend> make_cpu_backend();

#ifdef EXPANSE_HAVE_VULKAN
/// device: index as listed by list_vulkan_devices(), or -1 for the best one.
std::unique_ptr<Backend> make_vulkan_backend(int device);
/// Throws Error(backend_unavailable) with the reason when there is no Vulkan instance.
std::vector<DeviceDescription> list_vulkan_devices();
#endif

#ifdef EXPANSE_HAVE_CUDA
std::unique_ptr<Backend> make_cuda_backend(int device);
std::vector<DeviceDescription> list_cuda_devices();
#endif

}  // namespace expanse::detail
