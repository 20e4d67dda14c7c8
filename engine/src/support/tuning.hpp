#pragma once
// The host's knobs: the CPU backend and the host stages every backend shares (input
// preparation, hull, bucket tree, seam completion, output). docs/tuning.md documents each one.
#include <cstddef>

namespace expanse::detail::host {

struct Tuning {
  /// Threads the host stages run on ($EXPANSE_HOST_THREADS, a positive number); 0: every
  /// hardware thread. Results never depend on it: tests and benchmarks set it to compare.
  std::size_t threads = 0;
};

/// The knobs from the environment, each left at its default where its variable is unset or
/// not valid. The only place the host reads the environment.
Tuning tuning_from_environment();

/// tuning_from_environment(), read once per process.
const Tuning& tuning();

}  // namespace expanse::detail::host
