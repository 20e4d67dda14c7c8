#pragma once
// Quantile cells' boundaries, with heavy tails weighed. Both GPU backends put an axis' column
// (or row) boundaries at quantiles of a sample of the sites' coordinates, so that clustered
// inputs keep every column at its share of the sites. But quantile cells are a product of two
// marginals, and along a heavy tail's diagonals a radial density crowds them: kuzmin's (Cauchy)
// tails are tail-dependent, so the cells where both quantiles are extreme hold a fixed share of
// a whole tail column (up to 2,000 sites a cell at 4096^2), and the searches there scan them
// whole. Weighing the outer samples more gives the tails more columns and rows.
//
// Measured (H100 and the 2-core VM, 2026-11-27): counted on the CPU (the CUDA
// walk, `expanse-bench-star-work`, two phases), the outer 1/40 of each axis weighed 3 times took
// kuzmin 4096^2 from 89.5 to 80.9 units a site and its sites past 2^11 units from 21,761 to
// 6,410 (at 10^6 87.3 -> 80.2, within 1% of that for weights of 2 to 4 over the outer 1 to 5%;
// boundaries that follow a sample histogram's crowding did worse). On the H100, kuzmin 4096^2
// GPU-only 67.0 / 67.4 -> 62.3 / 62.2 ms at 40,3; heavier weights did better there (62.5 at
// 40,2, 60.1 at 40,5; with the first pass's budget at 2^11, 59.3-59.7 for 40,5 to 40,8 and 30,6
// to 60,6); 40,5 takes kuzmin 2048^2 19.16 -> 18.28 ms and 512^2 4.02 -> 3.88. Vulkan on
// lavapipe, kuzmin 10^6, five runs each: 1,925-2,056 -> 1,794-1,989 ms host to host (medians
// 1,931 -> 1,862), its seam share 0.57% -> 0.19% (sites deferred 5,327 -> 1,712); on the H100,
// kuzmin 4096^2, its star shader 105.2 -> 97.7 ms. A light tail gains nothing (gaussian clusters
// at 10^6, counted: 78.5 -> 79.7 units), so only an axis whose outer 98% spans over
// kHeavyTailSpan times its middle half is weighed: Cauchy's spans 31.8 times, a gaussian's 3.4,
// an even spread's 2.
//
// The host and CUDA evaluate the same integer arithmetic on the same sorted sample, so the
// CUDA backend's host mirror (cuda_backend/star_host.hpp) and its kernels agree on every cell.
#include <cstdio>
#include <cstring>

#if defined(__CUDACC__)
#define EXPANSE_TAILS_HD __host__ __device__
#else
#define EXPANSE_TAILS_HD
#endif

namespace expanse::detail {

/// How an axis' quantile boundaries weigh its sample: the outer `tail` sorted samples on each
/// side count `factor` times the others, so the tails get `factor` times their share of columns
/// (or rows). {0, 1}: plain quantiles.
struct QuantileTails {
  int tail = 0;
  int factor = 1;
};

/// The outer 1/kTailShare of a heavy-tailed axis' sample on each side, weighed kTailFactor times.
inline constexpr int kTailShare = 40;
inline constexpr int kTailFactor = 5;
inline constexpr double kHeavyTailSpan = 8.0;

/// How heavy tails are weighed: their share of the sample (1 / share each side) and weight.
struct TailWeighing {
  int share = kTailShare;
  int factor = kTailFactor;
};

/// A backend's switch (EXPANSE_CUDA_TAILS; nullptr when unset): "0" weighs
/// nothing (plain quantiles, for comparisons), "share,factor" so; anything else the default.
inline TailWeighing parse_tail_weighing(const char* text) {
  TailWeighing w;
  if (!text) return w;
  if (std::strcmp(text, "0") == 0) {
    w.factor = 1;
  } else if (std::sscanf(text, "%d,%d", &w.share, &w.factor) != 2 || w.share < 3 || w.factor < 1) {
    w = TailWeighing{};
  }
  return w;
}

/// The weighing of an axis from its sorted sample.
EXPANSE_TAILS_HD inline QuantileTails quantile_tails(const double* sorted, int samples, TailWeighing w = {}) {
  if (w.factor <= 1 || samples < 4 * w.share) return {};
  const double middle = sorted[3 * (samples / 4)] - sorted[samples / 4];
  const double outer = sorted[samples - 1 - samples / 100] - sorted[samples / 100];
  if (!(outer > kHeavyTailSpan * middle)) return {};
  return {samples / w.share, w.factor};
}

/// Boundary j (1 .. cells - 1) from the sorted sample: its (j / cells)-quantile, the sample
/// weighed as `tails` says (plain quantiles by default).
EXPANSE_TAILS_HD inline double quantile_boundary(const double* sorted, int samples, int cells, int j,
                                                 QuantileTails tails = {}) {
  const long long f = tails.factor, tail = tails.tail, middle = samples - 2 * tail;
  const long long target = (middle + 2 * f * tail) * j / cells;  // in weighed samples
  const long long k = target < f * tail            ? target / f
                      : target < f * tail + middle ? tail + (target - f * tail)
                                                   : tail + middle + (target - f * tail - middle) / f;
  return sorted[k < samples ? k : samples - 1];
}

}  // namespace expanse::detail
