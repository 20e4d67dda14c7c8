#pragma once
// What a backend hands to the seam-completion stage (seam/seam_completion.hpp).
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "expanse/types.hpp"

namespace expanse::detail {

/// A set of triangles of the (perturbed) Delaunay triangulation, in site ids (SiteSet order),
/// counter-clockwise, each exactly once. Every triangle must be correct: a backend that cannot
/// decide an expansion exactly leaves it out (a *deferred* expansion) and the seam stage makes it.
struct PartialTriangulation {
  std::vector<Triangle> triangles;
  /// Optional adjacency (same convention as Mesh::neighbors, no_neighbor for hull *and* open
  /// edges). Empty: the seam stage derives it.
  std::vector<TriangleNeighbors> neighbors;
  /// When the backend's audit listed them: every link of `neighbors` left open inside the hull
  /// (no_neighbor on an edge that is not a hull edge), as 3 t + k, ascending. It spares the seam
  /// stage a read of the whole adjacency for them (400 MB at 4096^2).
  std::optional<std::vector<std::int64_t>> open_slots;
  std::size_t deferred_expansions = 0;  ///< for stats only
};

/// For backends, before filling `partial`: room for every triangle of the full triangulation
/// (2 sites - hull_sites - 2) in both vectors, so the seam stage appends in place. Without it
/// the seam stage moves both vectors to larger storage: at 16.8M sites, 805 MB of fresh pages
/// (about half a second of page faults on our hosts), for a seam of a few dozen triangles.
inline void reserve_full_triangulation(PartialTriangulation& partial, std::size_t sites, std::size_t hull_sites) {
  const std::size_t full = sites >= 3 ? 2 * sites - hull_sites - 2 : 0;
  partial.triangles.reserve(full);
  partial.neighbors.reserve(full);
}

/// For backends that download into `partial`: reserve_full_triangulation, then both vectors
/// resized to the full triangulation's size, ready to be written and shrunk to what was made
/// (which never moves them). Their ids are left unset (IdTriple): write every id that is kept.
/// With `recycled` (GrowInput::recycled), its vectors' storage is used where it is large enough:
/// their pages are already there. Fresh storage has its pages faulted in on all threads (805 MB
/// at 4096^2, 120-160 ms on the H100's host): call it while the device works.
void allocate_full_triangulation(PartialTriangulation& partial, std::size_t sites, std::size_t hull_sites,
                                 PartialTriangulation* recycled = nullptr);

}  // namespace expanse::detail
