#pragma once
// A minimal harness: these tests must be able to say "skipped" (exit 77) before any check runs,
// which is simplest without a framework.
#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "expanse/types.hpp"

namespace expanse::vulkan_tests {

struct Tally {
  long checks = 0;
  long failures = 0;
};
Tally& tally();

#define VK_CHECK_THAT(cond, ...)                                    \
  do {                                                              \
    ++::expanse::vulkan_tests::tally().checks;                      \
    if (!(cond)) {                                                  \
      if (::expanse::vulkan_tests::tally().failures++ < 20) {       \
        std::printf("FAILED %s:%d: %s: ", __FILE__, __LINE__, #cond); \
        std::printf(__VA_ARGS__);                                   \
        std::printf("\n");                                          \
      }                                                             \
    }                                                               \
  } while (0)

/// Triangles in a comparable form: each rotated to start at its smallest vertex, all sorted (the
/// backends' output order depends on atomics).
inline std::vector<Triangle> canonical(std::vector<Triangle> triangles) {
  for (Triangle& t : triangles) std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
  std::sort(triangles.begin(), triangles.end());
  return triangles;
}

void test_predicates();
void test_eft();
void test_backend();
void test_stars();
void test_device_passes();

}  // namespace expanse::vulkan_tests
