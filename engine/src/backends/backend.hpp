#pragma once
// Where the front grows. A Backend hides only the device (memory, dispatch); the pipeline owns
// input preparation, seam completion and output conventions.
#include <functional>
#include <future>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "expanse/mesh.hpp"
#include "expanse/options.hpp"
#include "expanse/triangulate.hpp"
#include "hull/convex_hull.hpp"
#include "input/site_set.hpp"
#include "backends/partial_triangulation.hpp"

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
  /// Host work the backend still runs after handing the result over, on its own thread (the
  /// CUDA backend releases the output's pinned pages while the seam and output stages use
  /// them). A std::async future: its destructor waits, and it is declared after `partial` so
  /// that it is destroyed first; the pipeline drops it before the output leaves triangulate().
  std::future<void> background;
};

/// The raw input, for a backend that validates nothing but sorts and merges duplicates on its
/// device (Backend::grow_from_input).
struct InputGrowInput {
  std::span<const Point2> points;
  const InputScan& scan;                 ///< scan_input(points): finite, scale, box
  /// The hull in input indices (convex_hull_of_input), which the host finds on another thread
  /// while the device starts: call it when the hull is needed (it waits). nullptr: the input is
  /// collinear or has fewer than three hull sites, and the backend must decline.
  std::function<const std::vector<std::int32_t>*()> hull;
  const Layout& layout;
  PartialTriangulation* recycled = nullptr;  ///< as GrowInput::recycled
};

/// What grow_from_input makes besides the growth: the sites and the hull as prepare_sites and
/// convex_hull would have made them for the rest of the pipeline (the sites in Morton order,
/// duplicates merged to their smallest input index; the order within a run of equal Morton
/// codes may differ).
struct InputGrowResult {
  GrowResult grown;
  SiteSet sites;
  Hull hull;
};

class Backend {
 public:
  virtual ~Backend() = default;
  virtual BackendKind kind() const = 0;
  virtual std::string device_name() const = 0;
  /// Grows the front as far as the device can decide exactly. Precondition: at least three
  /// sites, not all collinear.
  virtual GrowResult grow(const GrowInput& input) = 0;
  /// Prepares the sites itself and grows: the whole of prepare_sites, convex_hull's site ids
  /// and grow() in one. std::nullopt when it cannot (this layout, or an input too large for
  /// it): nothing was consumed, input.recycled included, and the caller prepares on the host
  /// and calls grow(). Precondition: the hull has at least three sites, not all collinear.
  virtual std::optional<InputGrowResult> grow_from_input(const InputGrowInput&) { return std::nullopt; }
  /// Whether grow_from_input may take this layout (the pipeline then scans the input and finds
  /// its hull for it, instead of preparing the sites).
  virtual bool prepares_sites(const Layout&) const { return false; }
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
