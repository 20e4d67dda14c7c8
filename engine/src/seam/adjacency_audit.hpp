#pragma once
// Decides whether a backend's adjacency can be trusted by the seam stage, in one parallel pass
// over the triangles plus work proportional to the seam. A spurious no_neighbor would make the
// seam stage grow triangles that already exist; a missing one would leave a hole.
#include <cstddef>

#include "hull/convex_hull.hpp"
#include "backends/partial_triangulation.hpp"

namespace expanse::detail {

/// True exactly when partial.neighbors is the adjacency of partial.triangles: each link leads to
/// the triangle across that edge (which links back), and an edge is marked open exactly when
/// no triangle lies across it (hull edges included). Exact: no hashing of fans.
/// Preconditions: triangles correct, CCW and distinct, in site ids of `hull`'s site set.
bool adjacency_is_trustworthy(const PartialTriangulation& partial, const Hull& hull);

}  // namespace expanse::detail
