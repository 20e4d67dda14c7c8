#pragma once
// The one error type of Expanse. Device errors keep their native code (VkResult, cudaError_t).
#include <cstdint>
#include <stdexcept>
#include <string>

namespace expanse {

enum class ErrorCode {
  invalid_argument,     ///< a parameter out of range (e.g. zero blocks)
  invalid_input,        ///< NaN or Inf coordinates
  parse_error,          ///< a malformed input file
  io_error,             ///< a file that cannot be opened, read or written
  backend_unavailable,  ///< the backend was not compiled in, or has no usable device
  device_error,         ///< a Vulkan or CUDA call failed; native_code() holds its result
  too_large,            ///< the input does not fit the device's limits
  internal,             ///< a broken invariant inside Expanse (a bug: please report)
};

/// Human-readable name of an error code ("invalid_input", ...).
const char* to_string(ErrorCode code) noexcept;

class Error : public std::runtime_error {
 public:
  Error(ErrorCode code, const std::string& message, std::int64_t native_code = 0)
      : std::runtime_error(message), code_(code), native_code_(native_code) {}
  ErrorCode code() const noexcept { return code_; }
  /// The device API's own result code for device_error (VkResult, cudaError_t), else 0.
  std::int64_t native_code() const noexcept { return native_code_; }

 private:
  ErrorCode code_;
  std::int64_t native_code_;
};

}  // namespace expanse
