#pragma once
// The entry point: points in, exact Delaunay triangulation out.
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "expanse/mesh.hpp"
#include "expanse/options.hpp"
#include "expanse/types.hpp"

namespace expanse {

/// Delaunay triangulation of `points`, identical triangle for triangle to CGAL's
/// Delaunay_triangulation_2 (its symbolic perturbation breaks cocircular ties).
/// Preconditions: coordinates finite (NaN/Inf -> Error(invalid_input) naming the point);
/// at most 2^31 - 1 points. Duplicates are merged, not rejected. Fewer than three distinct
/// sites, or all collinear, give no triangles and the hull only.
/// Throws Error(backend_unavailable) if the requested backend is not compiled in or has no
/// device, Error(too_large) if the input exceeds the device's limits.
Mesh triangulate(std::span<const Point2> points, const Options& options = {});

/// One device a backend can run on.
struct DeviceDescription {
  int index = 0;
  std::string name;
  std::string type;     ///< "cpu", "discrete", "integrated", "virtual", "software"
  bool fp64 = false;
  std::string details;  ///< limits worth knowing (subgroup size, max buffer range, memory)
};

struct BackendDescription {
  BackendKind kind = BackendKind::cpu;
  bool compiled = false;     ///< built into this binary
  std::string unavailable;   ///< why no device is usable, when compiled but unusable
  std::vector<DeviceDescription> devices;
};

/// Every backend Expanse knows, whether compiled in, and the devices each one sees.
std::vector<BackendDescription> describe_backends();

/// The backend BackendKind::automatic resolves to on this machine (cuda, then vulkan, then cpu).
BackendKind default_backend();

}  // namespace expanse

namespace expanse {

/// Keeps a backend (and its device, pipelines, buffers) alive across calls: what a caller that
/// triangulates repeatedly wants. Not thread-safe; one per thread. Device memory: the CUDA
/// backend allocates from the device's default memory pool and leaves what it freed there for
/// the next call (the pool is not trimmed); the Vulkan backend keeps its buffers in a context shared
/// by the whole process (the free function's calls included), grown to the largest input and
/// released after a call that leaves more than a quarter of the largest device-local heap
/// (EXPANSE_VULKAN_KEEP_MB sets the limit; 0 keeps nothing).
class Triangulator {
 public:
  /// Throws like triangulate() when the requested backend is unavailable.
  explicit Triangulator(const Options& options = {});
  ~Triangulator();
  Triangulator(Triangulator&&) noexcept;
  Triangulator& operator=(Triangulator&&) noexcept;
  Triangulator(const Triangulator&) = delete;
  Triangulator& operator=(const Triangulator&) = delete;

  /// Same contract as the free function triangulate().
  Mesh triangulate(std::span<const Point2> points);
  /// The same triangulation, written into `mesh`: the storage of its triangles and neighbours is
  /// filled again wherever it is large enough, so a caller that triangulates a frame at a time
  /// does not pay for fresh memory each time (at 4096^2 the two vectors hold 805 MB, whose page
  /// faults took 120-160 ms of a ~400 ms triangulation on the H100's host). The GPU backends'
  /// default layout reuses it; others may allocate anew. Errors in the input (the free
  /// function's Error(invalid_input), Error(too_large)) leave `mesh` as it was; any later error
  /// leaves it empty.
  void triangulate(std::span<const Point2> points, Mesh& mesh);
  /// The backend this triangulator resolved to (never automatic).
  BackendKind backend() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace expanse
