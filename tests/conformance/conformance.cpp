#include "conformance.hpp"

#include <catch2/catch.hpp>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include "expanse/check.hpp"
#include "expanse/error.hpp"
#include "expanse/triangulate.hpp"
#include "support/cgal_oracle.hpp"
#include "support/test_points.hpp"

namespace expanse::conformance {

Options options(const Layout& layout) {
  Options o;
  o.backend = backend_under_test();
  o.layout = layout;
  return o;
}

namespace {

// Everything one case verifies, as text: empty when the backend's mesh is right. Used both to
// report a failure and, while shrinking, to decide whether a smaller input still fails.
std::string first_difference(std::span<const Point2> points, const Options& opts) {
  Mesh mesh;
  try {
    mesh = triangulate(points, opts);
  } catch (const std::exception& e) {
    return std::string("triangulate threw: ") + e.what();
  }
  return differences_from_cgal(points, mesh, opts);
}

}  // namespace

std::string differences_from_cgal(std::span<const Point2> points, const Mesh& mesh, const Options& opts) {
  const auto oracle = test::cgal_delaunay(points);
  std::ostringstream out;
  const auto tri = test::compare_triangles(mesh.triangles, oracle.triangles);
  if (!tri.equal) out << tri.message << "\n";
  const auto hull = test::compare_hulls(mesh.hull, oracle.hull, oracle.dimension < 2);
  if (!hull.equal) out << hull.message << "\n";
  if (mesh.representative != oracle.representative) out << "representative map differs from CGAL's\n";
  const auto report = check_mesh(points, mesh);
  if (!report.ok) {
    out << "check_mesh:\n";
    for (const auto& p : report.problems) out << "  " << p << "\n";
  }
  if (opts.neighbors && mesh.neighbors.size() != mesh.triangles.size())
    out << "neighbors asked for, " << mesh.neighbors.size() << " given for " << mesh.triangles.size()
        << " triangles\n";
  const Stats& s = mesh.stats;
  if (s.input_points != points.size()) out << "stats.input_points " << s.input_points << "\n";
  if (s.sites != oracle.sites) out << "stats.sites " << s.sites << ", expected " << oracle.sites << "\n";
  if (s.duplicates != points.size() - oracle.sites) out << "stats.duplicates " << s.duplicates << "\n";
  if (s.triangles != mesh.triangles.size()) out << "stats.triangles " << s.triangles << "\n";
  if (s.hull_sites != mesh.hull.size()) out << "stats.hull_sites " << s.hull_sites << "\n";
  if (s.gpu_triangles + s.seam_triangles != s.triangles && !mesh.triangles.empty())
    out << "stats: gpu_triangles " << s.gpu_triangles << " + seam_triangles " << s.seam_triangles
        << " != triangles " << s.triangles << "\n";
  if (s.backend != to_string(opts.backend)) out << "stats.backend is '" << s.backend << "'\n";
  return out.str();
}

namespace {

// Greedy delta debugging: drop chunks (halves, quarters, ... single points) while the input
// still fails. Bounded in time: a report needs a small input, not a minimal one.
std::vector<Point2> shrink(std::vector<Point2> points, const Options& opts) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  std::size_t chunk = points.size() / 2;
  while (chunk >= 1 && std::chrono::steady_clock::now() < deadline) {
    bool removed = false;
    for (std::size_t start = 0; start < points.size() && std::chrono::steady_clock::now() < deadline;) {
      std::vector<Point2> trial(points.begin(), points.begin() + static_cast<std::ptrdiff_t>(start));
      const std::size_t end = std::min(points.size(), start + chunk);
      trial.insert(trial.end(), points.begin() + static_cast<std::ptrdiff_t>(end), points.end());
      if (!first_difference(trial, opts).empty()) {
        points = std::move(trial);
        removed = true;
      } else {
        start += chunk;
      }
    }
    if (!removed) chunk /= 2;
  }
  return points;
}

}  // namespace

void expect_matches_cgal(std::string_view label, std::span<const Point2> points, const Options& opts) {
  const std::string problems = first_difference(points, opts);
  INFO("case " << label << ", n = " << points.size() << ", backend " << to_string(opts.backend));
  if (!problems.empty() && std::getenv("EXPANSE_SHRINK") != nullptr) {
    const auto small = shrink(std::vector<Point2>(points.begin(), points.end()), opts);
    std::filesystem::create_directories("conformance-failures");
    const std::string file = "conformance-failures/" + std::string(to_string(opts.backend)) + "-" +
                             std::string(label) + ".txt";
    std::string why = first_difference(small, opts);
    for (std::size_t at = why.find('\n'); at != std::string::npos && at + 1 < why.size(); at = why.find('\n', at + 1))
      why.insert(at + 1, "# ");
    std::ofstream(file) << "# " << small.size() << " points (x y, hex floats); fails with:\n# " << why
                        << test::points_text(small);
    UNSCOPED_INFO("shrunk to " << small.size() << " points, written to " << file);
  }
  INFO(problems);
  CHECK(problems.empty());
}

}  // namespace expanse::conformance
