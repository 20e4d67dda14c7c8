// GLSL predicates (shaders/include/predicates.glsl) against the host's: the filter and the
// certificate must agree with exact_arith.hpp decision for decision, and every sign the device
// decides must be the exact sign. Near-degenerate inputs are where the device must say
// "uncertain" instead of guessing.
#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "backends/vulkan/vulkan_backend.hpp"
#include "host_device.h"
#include "harness.hpp"
#include "predicates/apex_filter.hpp"
#include "predicates/exact_arith.hpp"
#include "predicates/predicates.hpp"

namespace expanse::vulkan_tests {
namespace {

using detail::exact::uncertain;

struct Case {
  Point2 a, b, c, d;
};

std::vector<Case> make_cases() {
  std::mt19937_64 rng(20261122);
  std::uniform_real_distribution<double> unit(0.5, 1.0);
  std::uniform_real_distribution<double> signed_unit(-1.0, 1.0);
  std::vector<Case> cases;
  // Random, well-conditioned.
  for (int i = 0; i < 4000; ++i)
    cases.push_back({{unit(rng), unit(rng)}, {unit(rng), unit(rng)}, {unit(rng), unit(rng)},
                     {unit(rng), unit(rng)}});
  // Nearly collinear: c on the segment a-b, rounded, nudged by a few ulps.
  for (int i = 0; i < 4000; ++i) {
    Point2 a{signed_unit(rng), signed_unit(rng)}, b{signed_unit(rng), signed_unit(rng)};
    const double t = unit(rng) - 0.25;
    Point2 c{a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)};
    for (int k = 0; k < i % 4; ++k) c.x = std::nextafter(c.x, 2.0);
    Point2 d{signed_unit(rng), signed_unit(rng)};
    cases.push_back({a, b, c, d});
  }
  // Nearly cocircular: four points on a circle, rounded.
  for (int i = 0; i < 4000; ++i) {
    const double cx = signed_unit(rng) * 0.25, cy = signed_unit(rng) * 0.25, r = unit(rng) * 0.5;
    double angle[4];
    for (double& t : angle) t = unit(rng) * 12.0;
    std::sort(angle, angle + 3);
    Point2 p[4];
    for (int k = 0; k < 4; ++k) p[k] = {cx + r * std::cos(angle[k]), cy + r * std::sin(angle[k])};
    cases.push_back({p[0], p[1], p[2], p[3]});
  }
  // Integer grids (scaled by powers of two): collinear and cocircular exactly.
  for (int i = 0; i < 4000; ++i) {
    auto g = [&] { return double(int(rng() % 9)) * 0x1p-4; };
    cases.push_back({{g(), g()}, {g(), g()}, {g(), g()}, {g(), g()}});
  }
  // Squares of decimal grids (step 0.1, 0.01): cocircular up to rounding; every coordinate
  // difference exact, so incircle_exact_differences decides them.
  for (int i = 0; i < 2000; ++i) {
    const double step = i % 2 ? 0.1 : 0.01;
    const int x = int(rng() % 4000) + 1000, y = int(rng() % 4000) + 1000, w = int(rng() % 3) + 1;
    auto at = [&](int gx, int gy) { return Point2{step * gx, step * gy}; };
    cases.push_back({at(x, y), at(x + w, y), at(x + w, y + w), at(x, y + w)});
  }
  // Exactly cocircular integer points: (±3, ±4), (±5, 0), (0, ±5) on radius 5, scaled.
  const Point2 circle[] = {{3, 4}, {-3, 4}, {-5, 0}, {-3, -4}, {0, -5}, {3, -4}, {5, 0}, {4, 3}};
  for (int i = 0; i < 8; ++i)
    for (int j = 0; j < 8; ++j)
      for (int k = 0; k < 8; ++k)
        for (int l = 0; l < 8; l += 3) {
          auto s = [](Point2 p) { return Point2{p.x * 0x1p-3 + 0.5, p.y * 0x1p-3 + 0.5}; };
          cases.push_back({s(circle[i]), s(circle[j]), s(circle[k]), s(circle[l])});
        }
  return cases;
}

}  // namespace

void test_predicates() {
  auto context = detail::vk::shared_context(-1);
  const std::vector<Case> cases = make_cases();
  std::vector<double> flat;
  for (const Case& c : cases)
    for (const Point2& p : {c.a, c.b, c.c, c.d}) {
      flat.push_back(p.x);
      flat.push_back(p.y);
    }
  std::vector<std::int32_t> signs;
  std::vector<double> eft;
  detail::vk::run_predicate_kernel(*context, flat, signs, eft);

  long orient_uncertain = 0, incircle_uncertain = 0, apex_uncertain = 0, perturbed_checked = 0;
  long differences_decided = 0;
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const Case& c = cases[i];
    const std::int32_t* s = &signs[std::size_t(detail::vk::shared::PREDICATE_TEST_SIGNS) * i];
    namespace ex = detail::exact;
    const int host_of = ex::orient2d_filter(c.a.x, c.a.y, c.b.x, c.b.y, c.c.x, c.c.y);
    const int host_oc = ex::orient2d_certified(c.a.x, c.a.y, c.b.x, c.b.y, c.c.x, c.c.y);
    const int host_if =
        ex::incircle_filter(c.a.x, c.a.y, c.b.x, c.b.y, c.c.x, c.c.y, c.d.x, c.d.y);
    const int host_ic =
        ex::incircle_certified(c.a.x, c.a.y, c.b.x, c.b.y, c.c.x, c.c.y, c.d.x, c.d.y);
    const int exact_o = detail::orient2d_exact(c.a, c.b, c.c);
    const int exact_i = detail::incircle_exact(c.a, c.b, c.c, c.d);
    VK_CHECK_THAT(s[0] == host_of, "case %zu: orient filter device %d host %d", i, s[0], host_of);
    VK_CHECK_THAT(s[1] == host_oc, "case %zu: orient certificate device %d host %d", i, s[1], host_oc);
    VK_CHECK_THAT(s[2] == uncertain || s[2] == exact_o, "case %zu: orient device %d exact %d", i,
                  s[2], exact_o);
    VK_CHECK_THAT(s[3] == host_if, "case %zu: incircle filter device %d host %d", i, s[3], host_if);
    VK_CHECK_THAT(s[4] == host_ic, "case %zu: incircle certificate device %d host %d", i, s[4],
                  host_ic);
    VK_CHECK_THAT(s[5] == uncertain || s[5] == exact_i, "case %zu: incircle device %d exact %d", i,
                  s[5], exact_i);
    // The apex filters in a->b's frame: the host's decisions, and exact where they decide.
    const auto edge = ex::apex_edge(c.a.x, c.a.y, c.b.x, c.b.y);
    const auto c_lift = ex::apex_lift(edge, ex::apex_point(edge, c.c.x, c.c.y));
    const auto d_point = ex::apex_point(edge, c.d.x, c.d.y);
    const int host_apex[] = {ex::apex_orient_filter(c_lift), ex::apex_orient_filter(ex::apex_lift(edge, d_point)),
                             ex::apex_incircle_filter(c_lift, d_point)};
    const int exact_apex[] = {exact_o, detail::orient2d_exact(c.a, c.b, c.d), exact_i};
    for (int k = 0; k < 3; ++k) {
      VK_CHECK_THAT(s[7 + k] == host_apex[k], "case %zu: apex filter %d device %d host %d", i, k, s[7 + k],
                    host_apex[k]);
      VK_CHECK_THAT(s[7 + k] == uncertain || s[7 + k] == exact_apex[k], "case %zu: apex filter %d device %d exact %d",
                    i, k, s[7 + k], exact_apex[k]);
      apex_uncertain += s[7 + k] == uncertain;
    }
    // Incircle from exact differences: the host's decisions, and exact where they decide.
    const int host_id =
        ex::incircle_exact_differences_grown(c.a.x, c.a.y, c.b.x, c.b.y, c.c.x, c.c.y, c.d.x, c.d.y);
    VK_CHECK_THAT(s[10] == host_id, "case %zu: incircle from exact differences device %d host %d", i, s[10], host_id);
    VK_CHECK_THAT(s[10] == uncertain || s[10] == exact_i, "case %zu: incircle from exact differences device %d exact %d",
                  i, s[10], exact_i);
    differences_decided += s[10] != uncertain && s[5] == uncertain;
    // orient2d from exact differences: exact, and decided whenever the differences are exact.
    double e0, e1, e2, e3;
    ex::two_diff(c.a.x, c.c.x, e0);
    ex::two_diff(c.b.y, c.c.y, e1);
    ex::two_diff(c.a.y, c.c.y, e2);
    ex::two_diff(c.b.x, c.c.x, e3);
    const bool exact_differences = e0 == 0.0 && e1 == 0.0 && e2 == 0.0 && e3 == 0.0;
    VK_CHECK_THAT(s[11] == (exact_differences ? exact_o : uncertain), "case %zu: orient from exact differences device %d exact %d",
                  i, s[11], exact_o);
    orient_uncertain += s[2] == uncertain;
    incircle_uncertain += s[5] == uncertain;
    if (s[2] == 1 && s[6] != uncertain) {
      ++perturbed_checked;
      const int host_p = detail::incircle_perturbed(c.a, c.b, c.c, c.d);
      const bool distinct = !(c.d == c.a || c.d == c.b || c.d == c.c);
      if (distinct)
        VK_CHECK_THAT(s[6] == host_p, "case %zu: perturbed incircle device %d host %d", i, s[6],
                      host_p);
    }
  }
  std::printf("predicates: %zu cases, device undecided: orient %ld, incircle %ld, apex filters %ld; "
              "perturbed compared %ld; decided from exact differences where the certificate could not %ld\n",
              cases.size(), orient_uncertain, incircle_uncertain, apex_uncertain, perturbed_checked,
              differences_decided);
  VK_CHECK_THAT(differences_decided >= 1000, "exact differences decided only %ld cases", differences_decided);
  // The near-degenerate families must exercise the "uncertain" answer, or this test is weak.
  VK_CHECK_THAT(orient_uncertain > 0 && incircle_uncertain > 0 && apex_uncertain > 0, "no undecided cases generated");
}

void test_eft() {
  auto context = detail::vk::shared_context(-1);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::vector<double> flat;
  const std::size_t count = 20000;
  for (std::size_t i = 0; i < count; ++i) {
    // Mix magnitudes so sums and products lose low bits in every way.
    const double scale = std::ldexp(1.0, int(rng() % 60) - 30);
    flat.push_back(unit(rng));
    flat.push_back(unit(rng) * scale);
    flat.push_back(unit(rng) * scale * scale);
    for (int k = 0; k < 5; ++k) flat.push_back(0.5);
  }
  std::vector<std::int32_t> signs;
  std::vector<double> eft;
  detail::vk::run_predicate_kernel(*context, flat, signs, eft);
  for (std::size_t i = 0; i < count; ++i) {
    const double x = flat[8 * i], y = flat[8 * i + 1], z = flat[8 * i + 2];
    double sum_error, product_error;
    detail::exact::two_sum(x, y, sum_error);
    const double product = detail::exact::two_product(x, y, product_error);
    const double unfused = x * y + z;  // -ffp-contract=off: two roundings
    VK_CHECK_THAT(eft[4 * i] == sum_error, "two_sum(%a, %a) error %a, host %a", x, y, eft[4 * i],
                  sum_error);
    VK_CHECK_THAT(eft[4 * i + 1] == product && eft[4 * i + 2] == product_error,
                  "two_product(%a, %a) = %a + %a, host %a + %a", x, y, eft[4 * i + 1],
                  eft[4 * i + 2], product, product_error);
    VK_CHECK_THAT(eft[4 * i + 3] == unfused, "precise x*y+z = %a, two roundings give %a (fma?)",
                  eft[4 * i + 3], unfused);
  }
  VK_CHECK_THAT(detail::vk::eft_self_test(*context).empty(), "start-up self-test fails");
}

}  // namespace expanse::vulkan_tests
