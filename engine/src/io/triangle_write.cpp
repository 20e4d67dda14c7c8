// Writers for Triangle's .node, .ele and .neigh files.
#include <string>

#include "expanse/error.hpp"
#include "expanse/io.hpp"
#include "io/atomic_file.hpp"

namespace expanse {
namespace {

void check_base(int first_index) {
  if (first_index != 0 && first_index != 1) {
    throw Error(ErrorCode::invalid_argument,
                "first index must be 0 or 1, not " + std::to_string(first_index));
  }
}

}  // namespace

void write_node_file(const std::filesystem::path& path, std::span<const Point2> points,
                     int first_index) {
  check_base(first_index);
  io_detail::AtomicFile file(path);
  io_detail::TextWriter out(file);
  out.integer(static_cast<long long>(points.size())).text(" 2 0 0\n");
  long long number = first_index;
  for (const Point2& p : points) {
    out.integer(number++).space().real(p.x).space().real(p.y).newline();
  }
  out.flush();
  file.commit();
}

void write_ele_file(const std::filesystem::path& path, const Mesh& mesh, int first_index) {
  check_base(first_index);
  io_detail::AtomicFile file(path);
  io_detail::TextWriter out(file);
  out.integer(static_cast<long long>(mesh.triangles.size())).text(" 3 0\n");
  long long number = first_index;
  for (const Triangle& t : mesh.triangles) {
    out.integer(number++);
    for (std::int32_t v : t) out.space().integer(static_cast<long long>(v) + first_index);
    out.newline();
  }
  out.flush();
  file.commit();
}

void write_neigh_file(const std::filesystem::path& path, const Mesh& mesh, int first_index) {
  check_base(first_index);
  if (mesh.neighbors.size() != mesh.triangles.size()) {
    throw Error(ErrorCode::invalid_argument,
                path.string() + ": the mesh has no neighbors (triangulate with Options::neighbors)");
  }
  io_detail::AtomicFile file(path);
  io_detail::TextWriter out(file);
  out.integer(static_cast<long long>(mesh.neighbors.size())).text(" 3\n");
  long long number = first_index;
  for (const auto& row : mesh.neighbors) {
    out.integer(number++);
    for (std::int32_t n : row) {
      out.space().integer(n == no_neighbor ? -1LL : static_cast<long long>(n) + first_index);
    }
    out.newline();
  }
  out.flush();
  file.commit();
}

}  // namespace expanse
