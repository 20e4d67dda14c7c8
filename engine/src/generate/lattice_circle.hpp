#pragma once
// Integer points that lie exactly on one circle x^2 + y^2 = N centred at the origin.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

namespace expanse::generate_detail {

/// At least `count` distinct integer points (x, y) with x^2 + y^2 = N for one N, |x|, |y| < 2^50
/// (so exact as doubles), or nothing if no such N under 2^100 has that many.
std::optional<std::vector<std::pair<std::int64_t, std::int64_t>>> lattice_circle(std::size_t count);

}  // namespace expanse::generate_detail
