#include "support/tuning.hpp"

#include <cstdlib>

namespace expanse::detail::host {

Tuning tuning_from_environment() {
  Tuning tuning;
  if (const char* text = std::getenv("EXPANSE_HOST_THREADS")) {
    const long value = std::strtol(text, nullptr, 10);
    if (value > 0) tuning.threads = static_cast<std::size_t>(value);
  }
  return tuning;
}

const Tuning& tuning() {
  static const Tuning from_environment = tuning_from_environment();
  return from_environment;
}

}  // namespace expanse::detail::host
