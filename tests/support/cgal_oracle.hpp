#pragma once
// CGAL's Delaunay_triangulation_2 as the reference every backend is compared with.
// CGAL stays out of this header: it compiles slowly, and only cgal_oracle.cpp pays for it.
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "expanse/mesh.hpp"
#include "expanse/types.hpp"

namespace expanse::test {

/// What CGAL says about a point set, in input indices.
struct OracleResult {
  /// Finite faces, counter-clockwise, each vertex the first occurrence of its point.
  std::vector<Triangle> triangles;
  /// Hull sites counter-clockwise with collinear hull sites included (read off the faces
  /// incident to the infinite vertex). All collinear: the sites sorted by (x, y).
  std::vector<std::int32_t> hull;
  /// representative[i]: smallest input index of a point equal to point i.
  std::vector<std::int32_t> representative;
  std::size_t sites = 0;     ///< distinct points
  int dimension = -1;        ///< CGAL's dimension(): 2 when there are triangles
};

/// Triangulates `points` (finite coordinates) with CGAL's Exact_predicates_inexact_constructions
/// kernel. Duplicates are merged here before CGAL sees them, because range insertion spatially
/// sorts and would otherwise keep an arbitrary copy.
OracleResult cgal_delaunay(std::span<const Point2> points);

/// A Mesh made from the oracle's answer (neighbors computed, stats left empty): a correct mesh
/// that does not depend on expanse::triangulate.
Mesh mesh_from_oracle(const OracleResult& oracle);

/// neighbors[t][k] = the triangle across the edge opposite triangles[t][k], or no_neighbor.
/// Edges shared by more than two triangles get an arbitrary partner (garbage in, garbage out).
std::vector<TriangleNeighbors> compute_neighbors(std::span<const Triangle> triangles);

/// Rotates each triangle so its smallest index comes first (orientation kept), then sorts.
std::vector<Triangle> canonical_triangles(std::span<const Triangle> triangles);

/// Rotates a cyclic hull so its smallest index comes first.
std::vector<std::int32_t> canonical_hull(std::span<const std::int32_t> hull);

struct Comparison {
  bool equal = true;
  std::string message;  ///< counts and the first differing items when !equal
};

/// Triangle-for-triangle comparison, independent of triangle order and rotation.
Comparison compare_triangles(std::span<const Triangle> actual, std::span<const Triangle> expected);

/// Hull comparison as a cycle (any starting site). When `collinear`, the hull is a sequence
/// along a line whose direction nobody fixed: it must equal `expected` or its reverse.
Comparison compare_hulls(std::span<const std::int32_t> actual,
                         std::span<const std::int32_t> expected, bool collinear);

}  // namespace expanse::test
