// Point generators: determinism, exact counts, and the property each distribution promises.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <set>
#include <string>

#include "expanse/error.hpp"
#include "expanse/generate.hpp"

using expanse::Point2;

namespace {

std::uint64_t fingerprint(const std::vector<Point2>& points) {
  // FNV-1a over the raw bits: any difference in any bit changes it.
  std::uint64_t h = 1469598103934665603ULL;
  for (const Point2& p : points) {
    unsigned char bytes[sizeof(Point2)];
    std::memcpy(bytes, &p, sizeof p);
    for (unsigned char b : bytes) h = (h ^ b) * 1099511628211ULL;
  }
  return h;
}

std::size_t distinct(std::vector<Point2> points) {
  std::sort(points.begin(), points.end(),
            [](const Point2& a, const Point2& b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
  return static_cast<std::size_t>(std::unique(points.begin(), points.end()) - points.begin());
}

bool is_integer(double v) { return std::isfinite(v) && v == std::floor(v); }

}  // namespace

TEST_CASE("every distribution gives exactly n points, deterministically", "[generate]") {
  for (const std::string& name : expanse::distribution_names()) {
    INFO(name);
    CHECK(!expanse::describe_distribution(name).empty());
    for (std::size_t n : {0u, 1u, 2u, 3u, 7u, 100u, 1000u}) {
      INFO(n);
      auto a = expanse::generate_points(name, n, 1234);
      auto b = expanse::generate_points(name, n, 1234);
      REQUIRE(a.size() == n);
      CHECK(fingerprint(a) == fingerprint(b));
      for (const Point2& p : a) CHECK((std::isfinite(p.x) && std::isfinite(p.y)));
    }
    const bool seedless = name == "grid" || name == "rotated_grid";
    if (!seedless) {
      CHECK(fingerprint(expanse::generate_points(name, 100, 1)) !=
            fingerprint(expanse::generate_points(name, 100, 2)));
    }
  }
}

TEST_CASE("generators give the same bits on every platform", "[generate]") {
  // Pinned values: a change here means old benchmark inputs can no longer be regenerated.
  // (If a change is intended, say so in docs/benchmarks.md and update the values.)
  auto u = expanse::generate_points("uniform", 2, 0);
  CHECK(u[0].x == 0x1.33d8be6d96ebep-1);
  CHECK(u[1].y == 0x1.aa9653c498b4ap-2);
  const std::pair<const char*, std::uint64_t> pinned[] = {
      {"uniform", 0x08347bfa9965196fULL},        {"gaussian", 0x603e1a949e6c4bdbULL},
      {"clusters", 0xc6beb02ce6471a27ULL},       {"grid", 0x8ca16a55ac7a9703ULL},
      {"rotated_grid", 0x5860a166e1d5cc30ULL},   {"circle", 0xfada1d338c85dfb4ULL},
      {"disk", 0xfe57c28c80b8d886ULL},           {"kuzmin", 0xd4802b30711e3494ULL},
      {"line", 0x60fc77db8fc5918fULL},           {"collinear_plus_one", 0x15da4558ea5a8c7bULL},
      {"duplicates", 0xd57c36fed9e72e0cULL},     {"offset", 0x0cd403063eeef8c4ULL},
      {"near_collinear", 0x7d860f3a9956457cULL}, {"thin_circle", 0x79934e240ddca98aULL},
      {"tiny", 0x3be8e32a2a02ff1fULL},           {"huge", 0xdd4eed5dd97de3d7ULL},
  };
  for (const auto& [name, value] : pinned) {
    INFO(name);
    CHECK(fingerprint(expanse::generate_points(name, 1000, 42)) == value);
  }
}

TEST_CASE("unknown distribution names the valid ones", "[generate]") {
  try {
    expanse::generate_points("nope", 10, 0);
    FAIL("no error");
  } catch (const expanse::Error& e) {
    CHECK(e.code() == expanse::ErrorCode::invalid_argument);
    const std::string message = e.what();
    CHECK(message.find("nope") != std::string::npos);
    CHECK(message.find("uniform") != std::string::npos);
    CHECK(message.find("kuzmin") != std::string::npos);
  }
}

TEST_CASE("distribution properties", "[generate]") {
  const std::size_t n = 1000;
  SECTION("uniform lies in the unit square") {
    for (const Point2& p : expanse::generate_points("uniform", n, 3))
      CHECK((p.x >= 0 && p.x < 1 && p.y >= 0 && p.y < 1));
  }
  SECTION("grid is an integer grid of distinct points") {
    auto points = expanse::generate_points("grid", n, 3);
    for (const Point2& p : points) CHECK((is_integer(p.x) && is_integer(p.y)));
    CHECK(distinct(points) == n);
    CHECK(std::max_element(points.begin(), points.end(), [](auto& a, auto& b) { return a.x < b.x; })->x == 31);
  }
  SECTION("rotated_grid is integer and is the grid turned by 3-4-5") {
    auto grid = expanse::generate_points("grid", n, 3);
    auto rotated = expanse::generate_points("rotated_grid", n, 3);
    for (std::size_t i = 0; i < n; ++i) {
      CHECK(rotated[i].x == 3 * grid[i].x - 4 * grid[i].y);
      CHECK(rotated[i].y == 4 * grid[i].x + 3 * grid[i].y);
    }
  }
  SECTION("circle: integer points exactly on one circle, and the centre") {
    for (std::size_t m : {2u, 5u, 9u, 100u, 5000u}) {
      auto points = expanse::generate_points("circle", m, 5);
      CHECK(distinct(points) == m);
      long double r2 = -1;
      std::size_t centres = 0;
      for (const Point2& p : points) {
        REQUIRE((is_integer(p.x) && is_integer(p.y)));
        if (p.x == 0 && p.y == 0) {
          ++centres;
          continue;
        }
        // |x|, |y| < 2^50 keeps x*x + y*y exact in __int128.
        const auto x = static_cast<__int128>(p.x), y = static_cast<__int128>(p.y);
        const auto here = static_cast<long double>(x * x + y * y);
        if (r2 < 0) r2 = here;
        CHECK(here == r2);
      }
      CHECK(centres == 1);
    }
  }
  SECTION("disk lies in the unit disk") {
    for (const Point2& p : expanse::generate_points("disk", n, 3)) CHECK(p.x * p.x + p.y * p.y < 1);
  }
  SECTION("kuzmin is dense at the centre with a far tail") {
    auto points = expanse::generate_points("kuzmin", 10000, 3);
    std::size_t inner = 0;
    double far = 0;
    for (const Point2& p : points) {
      const double r = std::hypot(p.x, p.y);
      inner += r < 1 ? 1 : 0;
      far = std::max(far, r);
    }
    // Mass within r = 1 is 1 - 1/sqrt(2) = 0.29.
    CHECK(inner > 2600);
    CHECK(inner < 3300);
    CHECK(far > 50);
  }
  SECTION("line is exactly collinear") {
    for (const Point2& p : expanse::generate_points("line", n, 3)) CHECK(p.y == 2 * p.x);
  }
  SECTION("collinear_plus_one has exactly one point off the x axis") {
    auto points = expanse::generate_points("collinear_plus_one", n, 3);
    CHECK(std::count_if(points.begin(), points.end(), [](auto& p) { return p.y != 0; }) == 1);
    CHECK(distinct(points) == n);
  }
  SECTION("duplicates has many exact duplicates") {
    auto points = expanse::generate_points("duplicates", n, 3);
    CHECK(distinct(points) <= n / 4);
    CHECK(distinct(points) > n / 8);
  }
  SECTION("offset is near 1e8 with a tiny spread") {
    for (const Point2& p : expanse::generate_points("offset", n, 3)) {
      CHECK((p.x >= 1e8 && p.x <= 1e8 + 1e-6 && p.y >= 1e8 && p.y <= 1e8 + 1e-6));
    }
  }
  SECTION("near_collinear is within ulps of y = 2x, and not all on it") {
    std::size_t off = 0;
    for (const Point2& p : expanse::generate_points("near_collinear", n, 3)) {
      CHECK(std::abs(p.y - 2 * p.x) < 1e-15);
      off += p.y != 2 * p.x ? 1 : 0;
    }
    CHECK(off > n / 2);
  }
  SECTION("thin_circle is within 1e-9 of the unit circle") {
    for (const Point2& p : expanse::generate_points("thin_circle", n, 3)) {
      CHECK(std::abs(std::hypot(p.x, p.y) - 1) < 1e-9);
    }
  }
  SECTION("tiny and huge have the promised magnitudes") {
    for (const Point2& p : expanse::generate_points("tiny", n, 3)) {
      CHECK((p.x < 1e-100 && p.y < 1e-100 && p.x >= 0 && p.y >= 0));
    }
    double big = 0;
    for (const Point2& p : expanse::generate_points("huge", n, 3)) {
      CHECK((p.x < 1e100 && p.y < 1e100));
      big = std::max(big, p.x);
    }
    CHECK(big > 1e99);
  }
  SECTION("gaussian forms two clusters") {
    std::size_t low = 0;
    for (const Point2& p : expanse::generate_points("gaussian", n, 3)) low += p.x + p.y < 1 ? 1 : 0;
    CHECK(low > n * 2 / 5);
    CHECK(low < n * 3 / 5);
  }
}
