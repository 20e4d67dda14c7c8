#pragma once
// Triangle's file formats (https://www.cs.cmu.edu/~quake/triangle.html): .node, .ele, .neigh.
// Every writer is atomic: it writes a temporary file beside the target and renames it, so a
// failure never leaves a partial or stale-looking output behind.
#include <filesystem>
#include <span>
#include <vector>

#include "expanse/mesh.hpp"
#include "expanse/types.hpp"

namespace expanse {

/// The contents of a .node file that Expanse uses; attributes and boundary markers are dropped.
struct NodeFile {
  std::vector<Point2> points;
  int first_index = 0;  ///< 0 or 1: the number of the first vertex in the file
};

/// Reads a .node file. Comments ('#' to end of line) and blank lines may appear anywhere;
/// vertices must be numbered consecutively from 0 or 1; dimension must be 2.
/// Throws Error(io_error) if the file cannot be read, Error(parse_error, "FILE:LINE: ...") for
/// malformed content, wrong counts, or a non-finite coordinate.
NodeFile read_node_file(const std::filesystem::path& path);

/// Writes points as a .node file (no attributes, no markers), numbered from first_index (0 or 1),
/// coordinates in shortest round-trip form. Throws Error(io_error) on failure (no file left).
void write_node_file(const std::filesystem::path& path, std::span<const Point2> points,
                     int first_index = 0);

/// Writes mesh.triangles as a .ele file, vertex and triangle numbers offset by first_index
/// (0 or 1, normally the .node file's). Throws Error(io_error) on failure (no file left).
void write_ele_file(const std::filesystem::path& path, const Mesh& mesh, int first_index = 0);

/// Writes mesh.neighbors as a .neigh file: neighbour k is across from vertex k, numbered from
/// first_index; -1 (no neighbour) stays -1 whatever the base, as in Triangle.
/// Precondition: mesh.neighbors is filled (Options::neighbors). Throws Error(invalid_argument)
/// if it is not, Error(io_error) on write failure (no file left).
void write_neigh_file(const std::filesystem::path& path, const Mesh& mesh, int first_index = 0);

/// The contents of a .ele file: triangles converted back to 0-based vertex ids.
struct EleFile {
  std::vector<Triangle> triangles;
  int first_index = 0;
};

/// Reads a .ele file with three nodes per triangle (attributes ignored). Vertex numbers are
/// taken relative to node_first_index (the base of the matching .node file).
/// Throws like read_node_file.
EleFile read_ele_file(const std::filesystem::path& path, int node_first_index = 0);

/// The contents of a .neigh file: neighbour triangle ids 0-based, no_neighbor for -1.
/// Throws like read_node_file.
std::vector<TriangleNeighbors> read_neigh_file(const std::filesystem::path& path);

}  // namespace expanse
