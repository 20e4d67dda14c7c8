#pragma once
// A small random source that gives the same numbers on every platform: xoshiro256** seeded by
// splitmix64, and transforms built from integer arithmetic, +, *, / and sqrt only (all
// correctly rounded by IEEE 754), never libm's log/sin/cos, whose last bits differ by library.
// Callers compile with -ffp-contract=off so no multiply-add is fused differently.
#include <cmath>
#include <cstdint>

namespace expanse::generate_detail {

class Random {
 public:
  explicit Random(std::uint64_t seed) {
    std::uint64_t z = seed;
    for (auto& word : s_) word = splitmix64(z);
  }

  std::uint64_t next() {
    const std::uint64_t result = rotl(s_[1] * 5, 7) * 9;
    const std::uint64_t t = s_[1] << 17;
    s_[2] ^= s_[0];
    s_[3] ^= s_[1];
    s_[1] ^= s_[2];
    s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = rotl(s_[3], 45);
    return result;
  }

  /// Uniform in [0, 1), a multiple of 2^-53.
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }

  /// Uniform integer in [0, bound); bound > 0. Multiply-shift: a bias below 2^-32 is harmless here.
  std::uint64_t below(std::uint64_t bound) {
    return static_cast<std::uint64_t>((static_cast<unsigned __int128>(next()) * bound) >> 64);
  }

  /// Approximately standard normal: Irwin-Hall sum of 12 uniforms, minus 6. Summed as
  /// integers, so the result is exact and identical everywhere; tails stop at +-6 sigma.
  double normal() {
    std::uint64_t sum = 0;
    for (int i = 0; i < 12; ++i) sum += next() >> 32;
    return static_cast<double>(static_cast<std::int64_t>(sum) - (std::int64_t{6} << 32)) * 0x1.0p-32;
  }

  /// Uniform in the unit disk, by rejection from the square.
  void in_disk(double& x, double& y) {
    do {
      x = 2.0 * uniform() - 1.0;
      y = 2.0 * uniform() - 1.0;
    } while (x * x + y * y >= 1.0);
  }

  /// Uniform direction on the unit circle: a disk point pushed out to radius 1 (sqrt only).
  void on_circle(double& x, double& y) {
    double r2 = 0.0;
    do {
      in_disk(x, y);
      r2 = x * x + y * y;
    } while (r2 < 1e-6);
    const double r = std::sqrt(r2);
    x /= r;
    y /= r;
  }

 private:
  static std::uint64_t rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
  static std::uint64_t splitmix64(std::uint64_t& z) {
    std::uint64_t x = (z += 0x9e3779b97f4a7c15ULL);
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
    return x ^ (x >> 31);
  }
  std::uint64_t s_[4];
};

/// Fisher-Yates with Random::below, so the order is the same everywhere (std::shuffle is not).
template <class T>
void shuffle(T* data, std::size_t n, Random& random) {
  for (std::size_t i = n; i > 1; --i) {
    std::size_t j = static_cast<std::size_t>(random.below(i));
    std::swap(data[i - 1], data[j]);
  }
}

}  // namespace expanse::generate_detail
