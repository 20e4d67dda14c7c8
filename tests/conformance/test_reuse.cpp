// Triangulator::triangulate(points, mesh): the mesh's storage filled again, the result the same
// as a fresh triangulation's, on the backend under test.
#include <catch2/catch.hpp>

#include <limits>
#include <vector>

#include "conformance.hpp"
#include "expanse/error.hpp"
#include "expanse/triangulate.hpp"
#include "support/test_points.hpp"

using namespace expanse;
using namespace expanse::conformance;

namespace {

void require_same(const Mesh& reused, const Mesh& before) {
  CHECK(reused.triangles == before.triangles);
  CHECK(reused.neighbors == before.neighbors);
  CHECK(reused.hull == before.hull);
  CHECK(reused.representative == before.representative);
  CHECK(reused.stats.triangles == before.stats.triangles);
}

}  // namespace

TEST_CASE("a reused mesh gets the fresh triangulation, growing, shrinking and degenerate", "[reuse]") {
  Triangulator triangulator(options());
  Mesh mesh;
  // Larger, smaller (the storage is larger than needed), larger again (it grows), duplicates,
  // cocircular, then inputs with no triangles at all.
  const std::vector<std::vector<Point2>> inputs = {
      test::points::uniform(20000, 1),   test::points::gaussian(5000, 2),
      test::points::kuzmin(30000, 3),    test::points::duplicates(8000, 4),
      test::points::grid(6000, 5),       test::points::uniform(20000, 6),
      {{0, 0}, {1, 1}, {2, 2}},          {{1, 2}},
      test::points::uniform(3000, 7)};
  for (std::size_t k = 0; k < inputs.size(); ++k) {
    INFO("input " << k << ": " << inputs[k].size() << " points");
    const Triangle* storage_before = mesh.triangles.data();
    const std::size_t capacity_before = mesh.triangles.capacity();
    triangulator.triangulate(inputs[k], mesh);
    CHECK(differences_from_cgal(inputs[k], mesh, options()) == "");
    if (mesh.stats.backend != "cpu" && capacity_before >= 2 * inputs[k].size() && !mesh.triangles.empty())
      CHECK(mesh.triangles.data() == storage_before);  // filled in place, not allocated anew
  }
}

TEST_CASE("a reused mesh is left as it was when the input is refused", "[reuse][errors]") {
  Triangulator triangulator(options());
  Mesh mesh;
  auto points = test::points::uniform(5000, 9);
  triangulator.triangulate(points, mesh);
  const Mesh before = mesh;
  points[1234].y = std::numeric_limits<double>::quiet_NaN();
  try {
    triangulator.triangulate(points, mesh);
    FAIL("no error for a NaN coordinate");
  } catch (const Error& e) {
    CHECK(e.code() == ErrorCode::invalid_input);
  }
  require_same(mesh, before);
}
