#pragma once
// Every cudaError_t becomes expanse::Error(device_error) carrying the native code, so a failing
// call is never silently ignored and callers see one error type for every backend.
#include <cuda_runtime_api.h>

#include <string>

#include "expanse/error.hpp"

namespace expanse::detail::cuda {

[[noreturn]] inline void throw_cuda(cudaError_t code, const char* what, const char* file, int line) {
  std::string message = std::string("CUDA: ") + what + " failed: " + cudaGetErrorName(code) + " (" +
                        cudaGetErrorString(code) + ") at " + file + ":" + std::to_string(line);
  if (code == cudaErrorMemoryAllocation)
    throw Error(ErrorCode::too_large, message + " (input does not fit device memory)",
                static_cast<std::int64_t>(code));
  throw Error(ErrorCode::device_error, message, static_cast<std::int64_t>(code));
}

}  // namespace expanse::detail::cuda

#define EXPANSE_CUDA(call)                                                              \
  do {                                                                                  \
    const cudaError_t expanse_cuda_status_ = (call);                                    \
    if (expanse_cuda_status_ != cudaSuccess)                                            \
      ::expanse::detail::cuda::throw_cuda(expanse_cuda_status_, #call, __FILE__, __LINE__); \
  } while (0)
