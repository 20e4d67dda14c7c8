#pragma once
// What a backend hands to the seam-completion stage.
#include <array>
#include <cstddef>
#include <cstdint>
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
  std::vector<std::array<std::int32_t, 3>> neighbors;
  std::size_t deferred_expansions = 0;  ///< for stats only
};

}  // namespace expanse::detail
