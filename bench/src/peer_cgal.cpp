// CGAL lives in this translation unit alone: it is by far the slowest thing here to compile.
#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>
#include <CGAL/version.h>

#include <array>
#include <cstdint>

#include "peers.hpp"
#include "support/timing.hpp"

namespace bench {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Vb = CGAL::Triangulation_vertex_base_with_info_2<std::int32_t, K>;
using Fb = CGAL::Triangulation_face_base_with_info_2<std::int32_t, K>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
using Delaunay = CGAL::Delaunay_triangulation_2<K, Tds>;
using expanse::detail::Clock;
using expanse::detail::ms_since;

}  // namespace

PeerRun run_cgal(std::span<const XY> points) {
  PeerRun run;
  auto t = Clock::now();
  // The (point, index) pairs are what lets CGAL report input indices, as Expanse does; building
  // them is part of the price of asking CGAL for an indexed mesh.
  std::vector<std::pair<K::Point_2, std::int32_t>> input;
  input.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
    input.emplace_back(K::Point_2(points[i].x, points[i].y), static_cast<std::int32_t>(i));
  run.stages_ms.emplace_back("convert", ms_since(t));

  t = Clock::now();
  Delaunay dt;
  dt.insert(input.begin(), input.end());  // spatial sort, then incremental insertion
  run.stages_ms.emplace_back("insert", ms_since(t));

  t = Clock::now();
  std::vector<std::array<std::int32_t, 3>> triangles;
  std::vector<std::array<std::int32_t, 3>> neighbors;
  triangles.reserve(dt.number_of_faces());
  std::int32_t next = 0;
  for (auto f = dt.finite_faces_begin(); f != dt.finite_faces_end(); ++f) {
    f->info() = next++;
    triangles.push_back({f->vertex(0)->info(), f->vertex(1)->info(), f->vertex(2)->info()});
  }
  neighbors.reserve(triangles.size());
  for (auto f = dt.finite_faces_begin(); f != dt.finite_faces_end(); ++f) {
    std::array<std::int32_t, 3> across{};
    for (int k = 0; k < 3; ++k) {
      auto g = f->neighbor(k);
      across[k] = dt.is_infinite(g) ? -1 : g->info();
    }
    neighbors.push_back(across);
  }
  run.stages_ms.emplace_back("extract", ms_since(t));

  for (auto& [name, ms] : run.stages_ms) run.total_ms += ms;
  run.triangles = triangles.size();
  return run;
}

std::string cgal_version() { return std::string("CGAL ") + CGAL_VERSION_STR; }

}  // namespace bench
