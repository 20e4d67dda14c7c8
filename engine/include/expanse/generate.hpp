#pragma once
// Deterministic test and benchmark point sets. The same (distribution, n, seed) gives the same
// points bit for bit on every platform and standard library: Expanse uses its own generator
// (xoshiro256** seeded by splitmix64) and its own transforms, never <random>'s distributions.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "expanse/types.hpp"

namespace expanse {

/// Names accepted by generate_points, in a stable order:
/// uniform, gaussian, clusters, grid, rotated_grid, circle, disk, kuzmin, line,
/// collinear_plus_one, duplicates, offset, near_collinear, thin_circle, tiny, huge.
std::vector<std::string> distribution_names();

/// One line describing a distribution (for `expanse generate --help`); empty if unknown.
std::string_view describe_distribution(std::string_view name);

/// Exactly n points of the named distribution. Preconditions: name is one of
/// distribution_names() (else Error(invalid_argument) listing them); n < 2^31.
std::vector<Point2> generate_points(std::string_view distribution, std::size_t n,
                                    std::uint64_t seed);

}  // namespace expanse
