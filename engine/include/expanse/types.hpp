#pragma once
// Basic value types shared by every part of Expanse.
#include <array>
#include <cstddef>
#include <cstdint>
#include <tuple>
#include <type_traits>

namespace expanse {

/// An input point. Coordinates are finite doubles; Expanse never changes them.
struct Point2 {
  double x = 0.0;
  double y = 0.0;
  friend bool operator==(const Point2&, const Point2&) = default;
};

/// Three 32-bit ids: a std::array<std::int32_t, 3> in every way (indexing, iteration, comparison,
/// structured bindings, conversion both ways) but one: value-initialisation leaves the ids
/// unset, as default-initialisation does, so `IdTriple{}`, `std::vector<IdTriple>(n)` and
/// `resize(n)` do not zero them. A mesh's two vectors are filled from the GPU, millions of
/// triples at a time (805 MB at 4096^2 points), and a zeroing pass before that, on one thread
/// per vector, only delays the download. Write every id you read.
struct IdTriple : std::array<std::int32_t, 3> {
  IdTriple() noexcept {}  // user-provided: value-initialisation calls it and zeroes nothing
  constexpr IdTriple(std::int32_t a, std::int32_t b, std::int32_t c) noexcept : std::array<std::int32_t, 3>{a, b, c} {}
  constexpr IdTriple(const std::array<std::int32_t, 3>& ids) noexcept : std::array<std::int32_t, 3>(ids) {}
};

/// Three indices into the caller's point array, counter-clockwise:
///
///        v2
///       /  \        neighbors[t][k] is the triangle across the edge opposite v_k,
///      /    \       or no_neighbor on the convex hull (scipy's convention).
///    v0 ---- v1
using Triangle = IdTriple;

/// The triangles across a triangle's three edges, neighbors[k] across from vertex k.
using TriangleNeighbors = IdTriple;

/// Sentinel for "no triangle across this edge" (a hull edge).
inline constexpr std::int32_t no_neighbor = -1;

}  // namespace expanse

// Structured bindings (auto [a, b, c] = triangle) as for std::array.
template <>
struct std::tuple_size<expanse::IdTriple> : std::integral_constant<std::size_t, 3> {};
template <std::size_t I>
struct std::tuple_element<I, expanse::IdTriple> {
  using type = std::int32_t;
};
