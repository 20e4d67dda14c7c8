// The number of ways to write N = prod p_i^e_i (p_i = 1 mod 4) as x^2 + y^2 is 4 prod (e_i + 1),
// and unique factorisation in the Gaussian integers lists them: with p = pi * conj(pi), every
// representation is a unit times prod pi^a * conj(pi)^(e - a), a = 0..e. So we pick exponents
// greedily (most representations per bit of N) and multiply out.
#include "generate/lattice_circle.hpp"

#include <cmath>

namespace expanse::generate_detail {
namespace {

struct Gaussian {
  std::int64_t re = 1, im = 0;
};

// |a|,|b| components stay below the product of the moduli, which stays below 2^50.
Gaussian multiply(Gaussian a, Gaussian b) {
  return {a.re * b.re - a.im * b.im, a.re * b.im + a.im * b.re};
}

struct Prime {
  std::int64_t p;
  Gaussian pi;  // pi * conj(pi) = p
  int exponent = 0;
};

std::vector<Prime> split_primes() {
  std::vector<Prime> primes;
  for (std::int64_t p = 5; p < 400; p += 4) {
    bool prime = true;
    for (std::int64_t d = 2; d * d <= p; ++d) prime = prime && (p % d != 0);
    if (!prime) continue;
    for (std::int64_t a = 1; a * a < p; ++a) {
      std::int64_t b2 = p - a * a;
      auto b = static_cast<std::int64_t>(std::sqrt(static_cast<double>(b2)));
      while (b * b < b2) ++b;
      if (b * b == b2) {
        primes.push_back({p, {a, b}});
        break;
      }
    }
  }
  return primes;
}

}  // namespace

std::optional<std::vector<std::pair<std::int64_t, std::int64_t>>> lattice_circle(std::size_t count) {
  std::vector<Prime> primes = split_primes();
  double log2_n = 0.0;  // log2 of N so far
  double reps = 4.0;
  while (reps < static_cast<double>(count)) {
    // Best gain in representations per bit of N.
    Prime* best = nullptr;
    double best_rate = 0.0;
    for (Prime& q : primes) {
      const double rate = std::log2((q.exponent + 2.0) / (q.exponent + 1.0)) / std::log2(double(q.p));
      if (rate > best_rate) {
        best_rate = rate;
        best = &q;
      }
    }
    log2_n += std::log2(static_cast<double>(best->p));
    if (log2_n > 100.0) return std::nullopt;
    reps = reps / (best->exponent + 1.0) * (best->exponent + 2.0);
    ++best->exponent;
  }

  std::vector<Gaussian> points{Gaussian{}};
  for (const Prime& q : primes) {
    if (q.exponent == 0) continue;
    const Gaussian conj{q.pi.re, -q.pi.im};
    std::vector<Gaussian> next;
    next.reserve(points.size() * (q.exponent + 1));
    for (int a = 0; a <= q.exponent; ++a) {
      Gaussian factor;
      for (int k = 0; k < a; ++k) factor = multiply(factor, q.pi);
      for (int k = a; k < q.exponent; ++k) factor = multiply(factor, conj);
      for (const Gaussian& z : points) next.push_back(multiply(z, factor));
    }
    points.swap(next);
  }
  std::vector<std::pair<std::int64_t, std::int64_t>> result;
  result.reserve(points.size() * 4);
  for (const Gaussian& z : points) {
    result.emplace_back(z.re, z.im);
    result.emplace_back(-z.im, z.re);
    result.emplace_back(-z.re, -z.im);
    result.emplace_back(z.im, -z.re);
  }
  return result;
}

}  // namespace expanse::generate_detail
