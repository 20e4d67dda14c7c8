// Start-up insurance: proves on this build and this machine that the error-free
// transformations are exact. The usual way to break them is a compiler contracting a*b-c into
// an fma (which makes two_product's remainder wrong), or a flush-to-zero mode eating
// subnormals; both fail one of the checks below.
#include <cmath>

#include "predicates/predicates.hpp"

namespace expanse::detail {
namespace {

// Opaque to the optimiser, so the checks run at run time with this build's code generation
// rather than being folded at compile time.
double runtime(double value) {
  volatile double sink = value;
  return sink;
}

bool two_product_is_exact() {
  // (1 + 2^-30)^2 = 1 + 2^-29 + 2^-60: the 2^-60 is the remainder. A contracted
  // product - a_high*b_high computes it wrongly.
  const double a = runtime(1.0 + 0x1p-30);
  double error;
  const double product = exact::two_product(a, a, error);
  if (product != 1.0 + 0x1p-29 || error != 0x1p-60) return false;
  // Opposite signs and a 53-bit operand.
  const double b = runtime(-(0x1p53 - 1.0));
  const double c = runtime(0x1p53 - 1.0);
  const double p2 = exact::two_product(b, c, error);
  // (2^53-1)^2 = 2^106 - 2^54 + 1; rounds to 2^106 - 2^54, remainder 1.
  return p2 == -(0x1p106 - 0x1p54) && error == -1.0;
}

bool two_sum_is_exact() {
  double error;
  const double sum = exact::two_sum(runtime(1.0), runtime(0x1p-60), error);
  if (sum != 1.0 || error != 0x1p-60) return false;
  const double diff = exact::two_diff(runtime(0x1p53), runtime(-1.0), error);
  // 2^53 + 1 is a tie, rounded to even (2^53): remainder 1.
  return diff == 0x1p53 && error == 1.0;
}

bool subnormals_are_kept() {
  // Flush-to-zero would turn this into 0 and break the filters' underflow slack.
  return runtime(0x1p-1060) * runtime(0x1p-10) == 0x1p-1070;
}

bool contraction_is_off() {
  // With fma contraction, a*a - p is evaluated as the exact remainder (nonzero) instead of the
  // rounded product minus itself (zero).
  // p is the rounded square, given as a constant so the compiler cannot reuse a*a for it.
  const double a = runtime(1.0 + 0x1p-30);
  const double p = runtime(1.0 + 0x1p-29);
  return a * a - p == 0.0;
}

bool predicates_decide_known_cases() {
  // Collinear points whose filter cannot decide, and an exactly cocircular quadruple.
  const Point2 a{0.5, 0.5}, b{12.0, 12.0}, c{24.0, 24.0};
  const Point2 a_nudged{0.5, std::nextafter(0.5, 1.0)};
  if (orient2d(a, b, c) != 0 || orient2d(a_nudged, b, c) != 1) return false;
  const Point2 p0{3, 4}, p1{-4, 3}, p2{-3, -4}, p3{4, -3};
  return incircle(p0, p1, p2, p3) == 0 && incircle_perturbed(p0, p1, p2, p3) != 0;
}

}  // namespace

bool predicates_self_test() {
  return two_product_is_exact() && two_sum_is_exact() && subnormals_are_kept() &&
         contraction_is_off() && predicates_decide_known_cases();
}

}  // namespace expanse::detail
