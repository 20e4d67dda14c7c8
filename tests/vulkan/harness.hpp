#pragma once
// A minimal harness: these tests must be able to say "skipped" (exit 77) before any check runs,
// which is simplest without a framework.
#include <cstdio>
#include <string>

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

void test_predicates();
void test_eft();
void test_backend();
void test_stars();
void test_device_passes();

}  // namespace expanse::vulkan_tests
