// The public value types behave as the std::array they replace, except for value-initialisation.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <map>
#include <type_traits>
#include <vector>

#include "expanse/types.hpp"

using namespace expanse;

static_assert(sizeof(Triangle) == 3 * sizeof(std::int32_t), "a vector of triangles is a flat array of ids");
static_assert(std::is_trivially_copyable_v<Triangle>, "copied to and from device buffers as bytes");
static_assert(std::is_same_v<Triangle, TriangleNeighbors>);
static_assert(!std::is_trivially_default_constructible_v<Triangle>,
              "value-initialisation must go through the empty constructor, not zero the ids");

TEST_CASE("IdTriple: indexing, comparison, ordering and bindings as std::array", "[types]") {
  const Triangle t{3, 1, 2};
  CHECK(t[0] == 3);
  CHECK(t.size() == 3);
  CHECK(t == Triangle{3, 1, 2});
  CHECK(t != Triangle{3, 2, 1});
  CHECK(Triangle{1, 2, 3} < Triangle{1, 3, 0});
  const std::array<std::int32_t, 3> plain = t;  // to std::array and back
  CHECK(Triangle(plain) == t);
  CHECK(t == plain);
  const auto [a, b, c] = t;
  CHECK((a == 3 && b == 1 && c == 2));
  std::vector<Triangle> sorted{{2, 0, 1}, {0, 1, 2}, {1, 2, 0}};
  std::sort(sorted.begin(), sorted.end());
  CHECK(sorted.front() == Triangle{0, 1, 2});
  std::map<Triangle, int> keyed{{t, 7}};
  CHECK(keyed.at(Triangle{3, 1, 2}) == 7);
}

TEST_CASE("IdTriple: a resized vector keeps what was written and adds room", "[types]") {
  std::vector<TriangleNeighbors> neighbors(4, {no_neighbor, no_neighbor, no_neighbor});
  neighbors[2] = {5, no_neighbor, 7};
  neighbors.resize(1000);
  for (std::size_t k = 4; k < neighbors.size(); ++k) neighbors[k] = {static_cast<std::int32_t>(k), 0, 0};
  CHECK(neighbors[2] == TriangleNeighbors{5, no_neighbor, 7});
  CHECK(neighbors[3] == TriangleNeighbors{no_neighbor, no_neighbor, no_neighbor});
  CHECK(neighbors[999][0] == 999);
}
