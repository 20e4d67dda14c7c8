#include <string>

#include "expanse/error.hpp"
#include "expanse/options.hpp"

namespace expanse {

const char* to_string(ErrorCode code) noexcept {
  switch (code) {
    case ErrorCode::invalid_argument: return "invalid_argument";
    case ErrorCode::invalid_input: return "invalid_input";
    case ErrorCode::parse_error: return "parse_error";
    case ErrorCode::io_error: return "io_error";
    case ErrorCode::backend_unavailable: return "backend_unavailable";
    case ErrorCode::device_error: return "device_error";
    case ErrorCode::too_large: return "too_large";
    case ErrorCode::internal: return "internal";
  }
  return "unknown";
}

std::string_view to_string(BackendKind kind) noexcept {
  switch (kind) {
    case BackendKind::automatic: return "auto";
    case BackendKind::cpu: return "cpu";
    case BackendKind::vulkan: return "vulkan";
    case BackendKind::cuda: return "cuda";
  }
  return "unknown";
}

BackendKind parse_backend_kind(std::string_view name) {
  for (BackendKind kind : {BackendKind::automatic, BackendKind::cpu, BackendKind::vulkan, BackendKind::cuda}) {
    if (name == to_string(kind)) return kind;
  }
  throw Error(ErrorCode::invalid_argument,
              "unknown backend '" + std::string(name) + "' (expected auto, cpu, vulkan or cuda)");
}

}  // namespace expanse
