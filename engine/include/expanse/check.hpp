#pragma once
// The validity checker used by every test and by `expanse triangulate --check`.
#include <span>
#include <string>
#include <vector>

#include "expanse/mesh.hpp"
#include "expanse/types.hpp"

namespace expanse {

struct CheckReport {
  bool ok = true;
  std::vector<std::string> problems;  ///< the first problems found (at most a few dozen)
};

/// Checks, exactly, that `mesh` is the Delaunay triangulation of `points`: every triangle CCW
/// and non-degenerate, every edge shared by at most two triangles with neighbors consistent,
/// every interior edge locally Delaunay (CGAL's perturbation breaks ties), the Euler count
/// 2n - h - 2, every distinct site used, and the hull CCW and convex.
/// Precondition: mesh came from triangulate(points, ...) (representatives filled in).
CheckReport check_mesh(std::span<const Point2> points, const Mesh& mesh);

}  // namespace expanse
