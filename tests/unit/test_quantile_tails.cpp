// Quantile cells' boundaries with heavy tails weighed (grid/quantile_tails.hpp), which both GPU
// backends' quantile cells use.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "grid/quantile_tails.hpp"

using namespace expanse::detail;

TEST_CASE("Quantile boundaries: heavy tails get more columns, light tails plain quantiles", "[grid]") {
  constexpr int samples = 1 << 16;
  std::mt19937_64 random(29);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<double> cauchy(samples), gaussian(samples), even(samples);
  for (int i = 0; i < samples; ++i) {
    cauchy[i] = std::tan(M_PI * (unit(random) - 0.5));
    gaussian[i] = normal(random);
    even[i] = unit(random);
  }
  for (auto* v : {&cauchy, &gaussian, &even}) std::sort(v->begin(), v->end());
  const QuantileTails heavy = quantile_tails(cauchy.data(), samples);
  CHECK(heavy.tail == samples / kTailShare);
  CHECK(heavy.factor == kTailFactor);
  CHECK(quantile_tails(gaussian.data(), samples).factor == 1);
  CHECK(quantile_tails(even.data(), samples).factor == 1);
  CHECK(quantile_tails(cauchy.data(), 100).factor == 1);  // too small a sample to tell
  for (const int cells : {8, 100, 2896}) {
    INFO(cells << " columns");
    int in_tails = 0, mismatches = 0, unordered = 0;
    double previous = -HUGE_VAL;
    for (int j = 1; j < cells; ++j) {
      // Unweighed, the boundaries are the plain quantiles.
      mismatches += quantile_boundary(cauchy.data(), samples, cells, j) !=
                    cauchy[static_cast<std::size_t>(j) * samples / cells];
      const double b = quantile_boundary(cauchy.data(), samples, cells, j, heavy);
      unordered += b < previous;
      previous = b;
      in_tails += b < cauchy[heavy.tail] || b >= cauchy[samples - heavy.tail];
    }
    CHECK(mismatches == 0);
    CHECK(unordered == 0);
    // The outer 2 / kTailShare of the sample hold kTailFactor times their share of the columns.
    const double expected = (cells - 1.0) * 2.0 * heavy.factor * heavy.tail /
                            (samples - 2.0 * heavy.tail + 2.0 * heavy.factor * heavy.tail);
    CHECK(std::abs(in_tails - expected) <= 2.0);
  }
}

TEST_CASE("Quantile boundaries: the backends' switch parses or falls back to the default", "[grid]") {
  CHECK(parse_tail_weighing(nullptr).factor == kTailFactor);
  CHECK(parse_tail_weighing("0").factor == 1);
  const TailWeighing set = parse_tail_weighing("25,4");
  CHECK(set.share == 25);
  CHECK(set.factor == 4);
  for (const char* bad : {"", "x", "2,4", "40,0", "40"}) {
    INFO("'" << bad << "'");
    CHECK(parse_tail_weighing(bad).share == kTailShare);
    CHECK(parse_tail_weighing(bad).factor == kTailFactor);
  }
}
