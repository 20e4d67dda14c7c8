// The conformance suite's runner: `expanse_conformance --backend cpu|vulkan|cuda [Catch args]`.
// A backend that is not compiled in, or sees no device, is *skipped* (exit 77, which ctest
// reports as skipped), never passed: a green run must mean the backend was really tested.
#define CATCH_CONFIG_RUNNER
#include <catch2/catch.hpp>

#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "conformance.hpp"
#include "expanse/error.hpp"
#include "expanse/triangulate.hpp"

namespace expanse::conformance {
namespace {
BackendKind chosen_backend = BackendKind::cpu;
}
BackendKind backend_under_test() { return chosen_backend; }
}  // namespace expanse::conformance

int main(int argc, char** argv) {
  using namespace expanse;
  constexpr int skip = 77;

  std::string name = "cpu";
  std::vector<char*> rest{argv[0]};
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--backend") == 0 && i + 1 < argc) {
      name = argv[++i];
    } else if (std::strncmp(argv[i], "--backend=", 10) == 0) {
      name = argv[i] + 10;
    } else {
      rest.push_back(argv[i]);
    }
  }

  BackendKind kind;
  try {
    kind = parse_backend_kind(name);
    if (kind == BackendKind::automatic) kind = default_backend();
  } catch (const Error& e) {
    std::fprintf(stderr, "expanse_conformance: %s\n", e.what());
    return 2;
  }
  const std::string shown(to_string(kind));

  const BackendDescription* found = nullptr;
  const auto backends = describe_backends();
  for (const auto& b : backends)
    if (b.kind == kind) found = &b;
  if (found == nullptr || !found->compiled) {
    std::printf("SKIPPED: %s backend: not compiled into this build\n", shown.c_str());
    return skip;
  }
  if (found->devices.empty()) {
    std::printf("SKIPPED: %s backend: %s\n", shown.c_str(),
                found->unavailable.empty() ? "no device" : found->unavailable.c_str());
    return skip;
  }
  std::printf("conformance: %s backend on %s\n", shown.c_str(), found->devices.front().name.c_str());
  std::fflush(stdout);

  conformance::chosen_backend = kind;
  Catch::Session session;
  const int parsed = session.applyCommandLine(static_cast<int>(rest.size()), rest.data());
  if (parsed != 0) return parsed;
  const int failed = session.run();
  // Catch returns the number of failures; 77 of them must not read as "skipped".
  return failed == skip ? skip + 1 : failed;
}
