#include "pipeline/backend_registry.hpp"

#include <string>

#include "expanse/error.hpp"
#include "expanse/triangulate.hpp"

namespace expanse {
namespace {

BackendDescription describe_cpu() {
  BackendDescription d;
  d.kind = BackendKind::cpu;
  d.compiled = true;
  d.devices.push_back({0, "CPU (sequential)", "cpu", true, "exact sequential incremental extrapolation"});
  return d;
}

template <class ListDevices>
void fill_devices(BackendDescription& d, ListDevices&& list) {
  try {
    d.devices = list();
    if (d.devices.empty()) d.unavailable = "no usable device found";
  } catch (const Error& e) {
    d.unavailable = e.what();
  }
}

BackendDescription describe_vulkan() {
  BackendDescription d;
  d.kind = BackendKind::vulkan;
#ifdef EXPANSE_HAVE_VULKAN
  d.compiled = true;
  fill_devices(d, [] { return detail::list_vulkan_devices(); });
#else
  d.unavailable = "not compiled in (build with libvulkan-dev and glslang-tools installed)";
#endif
  return d;
}

BackendDescription describe_cuda() {
  BackendDescription d;
  d.kind = BackendKind::cuda;
#ifdef EXPANSE_HAVE_CUDA
  d.compiled = true;
  fill_devices(d, [] { return detail::list_cuda_devices(); });
#else
  d.unavailable = "not compiled in (build with the CUDA toolkit's nvcc on the PATH or in /usr/local/cuda)";
#endif
  return d;
}

}  // namespace

std::vector<BackendDescription> describe_backends() {
  return {describe_cpu(), describe_vulkan(), describe_cuda()};
}

BackendKind default_backend() {
  for (const BackendDescription& d : {describe_cuda(), describe_vulkan()}) {
    if (d.compiled && !d.devices.empty()) return d.kind;
  }
  return BackendKind::cpu;
}

namespace detail {

std::unique_ptr<Backend> make_backend(BackendKind kind, int device) {
  if (kind == BackendKind::automatic) kind = default_backend();
  switch (kind) {
    case BackendKind::cpu:
      return make_cpu_backend();
    case BackendKind::vulkan:
#ifdef EXPANSE_HAVE_VULKAN
      return make_vulkan_backend(device);
#else
      break;
#endif
    case BackendKind::cuda:
#ifdef EXPANSE_HAVE_CUDA
      return make_cuda_backend(device);
#else
      break;
#endif
    case BackendKind::automatic:
      break;
  }
  (void)device;
  throw Error(ErrorCode::backend_unavailable,
              std::string("the ") + std::string(to_string(kind)) + " backend is not compiled into this build");
}

}  // namespace detail
}  // namespace expanse
