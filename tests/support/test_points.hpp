#pragma once
// Point families for the conformance suite and the checker's tests. They live here, not in the
// library's generator, so the tests keep control of their adversarial cases (exact
// cocircularity, scales whose squares under- or overflow, shuffled degenerate orders).
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "expanse/types.hpp"

namespace expanse::test {

/// A deterministic random source (splitmix64): the same points on every platform.
class TestRandom {
 public:
  explicit TestRandom(std::uint64_t seed) : state_(seed * 0x9e3779b97f4a7c15ULL + 0x632be59bd9b4e019ULL) {}
  std::uint64_t next();
  double uniform();                        ///< [0, 1), a multiple of 2^-53
  std::uint64_t below(std::uint64_t bound); ///< [0, bound)
  double normal();                         ///< Box-Muller; libm bits may differ, harmless here

 private:
  std::uint64_t state_;
};

template <class T>
void shuffle(std::vector<T>& v, TestRandom& random) {
  for (std::size_t i = v.size(); i > 1; --i) std::swap(v[i - 1], v[random.below(i)]);
}

/// Every family the conformance suite runs. `n` is the number of points asked for; families
/// whose size is fixed by their geometry (circle) document what they return.
namespace points {
std::vector<Point2> uniform(std::size_t n, std::uint64_t seed);
/// The paper's "gaussian": two normal clusters.
std::vector<Point2> gaussian(std::size_t n, std::uint64_t seed);
/// Twenty tight clusters at random centres.
std::vector<Point2> clusters(std::size_t n, std::uint64_t seed);
/// Kuzmin's disc: radial density ~ (1 + r^2)^(-3/2); heavy tail, dense core.
std::vector<Point2> kuzmin(std::size_t n, std::uint64_t seed);
/// Integer grid, row-major, the last row partial; shuffled so insertion order is no help.
std::vector<Point2> grid(std::size_t n, std::uint64_t seed);
/// The integer grid rotated exactly by atan(4/3): (3x - 4y, 4x + 3y), still integer,
/// every cocircular quadruple of the grid kept.
std::vector<Point2> rotated_grid_exact(std::size_t n, std::uint64_t seed);
/// The integer grid with step 0.1 from (10, 10): its squares are cocircular only up to the
/// rounding of 0.1 i, so the filters cannot decide them and the exact value is tiny, not zero.
std::vector<Point2> decimal_grid(std::size_t n, std::uint64_t seed);
/// The integer grid rotated by 30 degrees in floating point: nearly cocircular everywhere.
std::vector<Point2> rotated_grid_float(std::size_t n, std::uint64_t seed);
/// Every integer point on x^2 + y^2 = R^2 plus the centre, R the smallest product
/// 5 * 13 * 17 * 29 * 37 * 41 * ... that gives at least n - 1 of them (at most 2917 points).
std::vector<Point2> lattice_circle(std::size_t n, std::uint64_t seed);
/// n - 1 integer points on one line (shuffled) and one point off it.
std::vector<Point2> collinear_plus_one(std::size_t n, std::uint64_t seed);
/// n points drawn with repetition from about n / 3 uniform points.
std::vector<Point2> duplicates(std::size_t n, std::uint64_t seed);
/// The integer grid with every point repeated (exact cocircularity and duplicates together).
std::vector<Point2> grid_with_duplicates(std::size_t n, std::uint64_t seed);
/// 1e8 + uniform * 1e-6 in both coordinates: a few dozen representable values per axis.
std::vector<Point2> offset(std::size_t n, std::uint64_t seed);
/// Points within 1e-12 of the line y = 0.5 x + 0.25 over [0, 1].
std::vector<Point2> near_collinear(std::size_t n, std::uint64_t seed);
/// Points on the unit circle, radius perturbed by at most 1e-12.
std::vector<Point2> thin_circle(std::size_t n, std::uint64_t seed);
/// Uniform in [1e-100, 2e-100)^2.
std::vector<Point2> tiny(std::size_t n, std::uint64_t seed);
/// Uniform in [1e100, 2e100)^2.
std::vector<Point2> huge(std::size_t n, std::uint64_t seed);
/// The integer grid times 2^-340: exactly cocircular, and every degree-4 term underflows.
std::vector<Point2> tiny_grid(std::size_t n, std::uint64_t seed);
/// The integer grid times 2^330: exactly cocircular, and every degree-4 term overflows.
std::vector<Point2> huge_grid(std::size_t n, std::uint64_t seed);
/// The integer grid offset by 10^15: exact cocircularity where doubles have no bits to spare.
std::vector<Point2> offset_grid(std::size_t n, std::uint64_t seed);
/// Integer points on the boundary of a square only: every site is a hull site.
std::vector<Point2> square_boundary(std::size_t n, std::uint64_t seed);
/// Integer points on two parallel lines: every quadrilateral between them is cocircular.
std::vector<Point2> two_lines(std::size_t n, std::uint64_t seed);
/// Integer points on both axes, symmetric about the origin: cocircular in fours.
std::vector<Point2> cross(std::size_t n, std::uint64_t seed);
/// Uniform points in [0, 1e-200)^2 and four corners near 1e200: scaling all of them by one
/// power of two cannot keep the small ones exact.
std::vector<Point2> mixed_scale(std::size_t n, std::uint64_t seed);
}  // namespace points

using Generator = std::vector<Point2> (*)(std::size_t, std::uint64_t);

struct Family {
  const char* name;
  Generator generate;
  std::size_t max_n;  ///< largest size worth running (geometry- or time-limited)
};

/// All the families above, in a stable order.
const std::vector<Family>& families();

/// Points in a form that can be pasted into a test: one "x y" line each, hexadecimal floats.
std::string points_text(const std::vector<Point2>& points);

}  // namespace expanse::test
