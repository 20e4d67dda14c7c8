// expanse_vulkan_tests <predicates|eft|backend|stars|device|all>
#include <cstring>
#include <exception>

#include "backends/vulkan/vulkan_backend.hpp"
#include "harness.hpp"

namespace expanse::vulkan_tests {
Tally& tally() {
  static Tally t;
  return t;
}
}  // namespace expanse::vulkan_tests

int main(int argc, char** argv) {
  using namespace expanse;
  const char* suite = argc > 1 ? argv[1] : "all";
  try {
    auto context = detail::vk::shared_context(-1);
    std::printf("vulkan tests on %s (%s)\n", context->name().c_str(),
                context->physical().describe(0).details.c_str());
  } catch (const Error& e) {
    if (e.code() == ErrorCode::backend_unavailable) {
      std::printf("SKIPPED: no usable Vulkan device: %s\n", e.what());
      return 77;
    }
    std::printf("FAILED: %s\n", e.what());
    return 1;
  }
  try {
    const bool all = std::strcmp(suite, "all") == 0;
    if (all || std::strcmp(suite, "predicates") == 0) vulkan_tests::test_predicates();
    if (all || std::strcmp(suite, "eft") == 0) vulkan_tests::test_eft();
    if (all || std::strcmp(suite, "backend") == 0) vulkan_tests::test_backend();
    if (all || std::strcmp(suite, "stars") == 0) vulkan_tests::test_stars();
    if (all || std::strcmp(suite, "device") == 0) vulkan_tests::test_device_passes();
  } catch (const std::exception& e) {
    std::printf("FAILED with exception: %s\n", e.what());
    return 1;
  }
  const auto& t = vulkan_tests::tally();
  std::printf("%s: %ld checks, %ld failures\n", suite, t.checks, t.failures);
  if (t.checks == 0) return 1;  // a suite that checked nothing has not passed
  return t.failures == 0 ? 0 : 1;
}
