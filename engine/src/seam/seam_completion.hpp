#pragma once
// The seam-completion stage: the paper's sequential incremental extrapolation, seeded with the
// open front of a partial triangulation (or, when there is none, with one seed). Every backend
// hands its unfinished work here; the CPU backend is this stage seeded with one seed.
#include <cstddef>
#include <functional>

#include "grid/bucket_tree.hpp"
#include "hull/convex_hull.hpp"
#include "input/site_set.hpp"
#include "backends/partial_triangulation.hpp"

namespace expanse::detail {

struct SeamStats {
  std::size_t triangles_made = 0;   ///< triangles this stage added
  std::size_t open_edges = 0;       ///< front edges it started from
  std::uint64_t candidates_tested = 0;
  double setup_ms = 0.0;            ///< adjacency derived (if absent) and room reserved
  double open_ms = 0.0;             ///< the open edges found and queued
  double grow_ms = 0.0;             ///< the front grown to the full triangulation
};

/// Completes `mesh` in place to the full Delaunay triangulation: appends the missing triangles
/// and fills mesh.neighbors (derived first if empty). Preconditions: at least three sites, not
/// all collinear; every triangle of `mesh` is a correct Delaunay triangle, CCW, present once.
/// Throws Error(internal) if the result does not have 2n - h - 2 triangles.
///
/// `before_growth`, if set, is called once the growth no longer reads the triangles `mesh`
/// came with (their open edges are queued) and room for every triangle is reserved (the
/// triangles' storage stays where it is): the pipeline turns their site ids into input indices
/// there, on other threads, while the growth runs on this one. The growth only appends
/// triangles and writes links.
SeamStats complete_seam(const SiteSet& sites, const Hull& hull, const BucketTree& tree,
                        PartialTriangulation& mesh, const std::function<void()>& before_growth = {});

/// Adjacency of a set of triangles (no_neighbor where an edge has one triangle).
std::vector<TriangleNeighbors> derive_neighbors(const std::vector<Triangle>& triangles);

}  // namespace expanse::detail
