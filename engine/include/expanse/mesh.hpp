#pragma once
// The result of a triangulation.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "expanse/types.hpp"

namespace expanse {

/// Wall-clock or device time of one named stage, in milliseconds.
struct StageTime {
  std::string name;
  double ms = 0.0;
};

struct Stats {
  std::string backend;                ///< "cpu", "vulkan", "cuda"
  std::string device;                 ///< device name ("CPU" for the CPU backend)
  std::size_t input_points = 0;       ///< points given by the caller
  std::size_t sites = 0;              ///< distinct points
  std::size_t duplicates = 0;         ///< input_points - sites
  std::size_t hull_sites = 0;         ///< sites on the convex hull, collinear ones included
  std::size_t triangles = 0;
  std::size_t gpu_triangles = 0;      ///< triangles the backend's front growth made
  std::size_t seam_triangles = 0;     ///< triangles the CPU seam-completion stage made
  std::size_t deferred_expansions = 0;///< expansions the device could not decide and left to the CPU
  std::size_t iterations = 0;         ///< front iterations of the backend
  std::vector<StageTime> stages;      ///< host-side stages, in order
  std::vector<StageTime> device_stages;  ///< device-timed stages (timestamp queries / CUDA events)
  double total_ms = 0.0;              ///< triangulate() from call to return
};

struct Mesh {
  /// Counter-clockwise triangles; vertex ids index the caller's input array. A group of equal
  /// input points is represented by its first occurrence. The first stats.gpu_triangles were
  /// made by the backend's front growth, the remaining stats.seam_triangles by the CPU seam stage.
  std::vector<Triangle> triangles;
  /// neighbors[t][k]: the triangle across the edge opposite triangles[t][k], or no_neighbor.
  /// Empty when Options::neighbors is false.
  std::vector<TriangleNeighbors> neighbors;
  /// Sites on the convex hull in counter-clockwise order, collinear hull sites included.
  /// For all-collinear input: the sites in order along the line (no triangles).
  std::vector<std::int32_t> hull;
  /// representative[i]: the input index that stands for input point i (itself unless it
  /// repeats an earlier point).
  std::vector<std::int32_t> representative;
  Stats stats;
};

}  // namespace expanse
