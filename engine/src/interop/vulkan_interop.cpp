// expanse::vulkan::Triangulator: the application's device and queue in, a Mesh or its own index
// buffer filled out. The points are read back through the context's staging ring (a fixed
// 2 x 32 MiB of host-visible memory), the pipeline runs with a Vulkan backend on a Context that
// borrows the application's device, and the indices go back through the same ring.
// Vulkan structs are value-initialised from their sType alone ({VK_STRUCTURE_TYPE_...}).
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#include "expanse/vulkan_interop.hpp"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <limits>
#include <mutex>
#include <vector>

#include "backends/backend.hpp"
#include "backends/vulkan/vk_context.hpp"
#include "backends/vulkan/vulkan_backend.hpp"
#include "expanse/error.hpp"
#include "host_device.h"
#include "pipeline/run_pipeline.hpp"
#include "support/timing.hpp"

namespace expanse::vulkan {
namespace {

namespace vk = detail::vk;
using detail::Clock;
using detail::ms_since;
// Storage buffers bound at once by the kernel with the most (shaders/prepare_sites.comp), and the
// largest push-constant block.
constexpr std::uint32_t kernel_storage_buffers = 16;
constexpr std::uint32_t kernel_push_constant_bytes = std::uint32_t(std::max(
    {sizeof(vk::shared::StarParams), sizeof(vk::shared::BlockParams), sizeof(vk::shared::BucketParams),
     sizeof(vk::shared::PrepareParams), sizeof(vk::shared::RadixParams), sizeof(vk::shared::ScanParams),
     sizeof(vk::shared::AuditParams), sizeof(vk::shared::LinkParams), sizeof(vk::shared::PredicateTestParams)}));

void require(bool ok, ErrorCode code, const std::string& message) {
  if (!ok) throw Error(code, "Vulkan interop: " + message);
}

// The physical device as Expanse sees it, checked against what the kernels need, with the
// application's queue family in place of the one Expanse would have picked.
vk::PhysicalDevice check_device(const vk::Instance& instance, const DeviceHandles& h) {
  const vk::PhysicalDevice* found = nullptr;
  for (const auto& d : instance.devices())
    if (d.handle == h.physical_device) found = &d;
  require(found != nullptr, ErrorCode::invalid_argument,
          "physical_device is not one of the instance's physical devices");
  vk::PhysicalDevice d = *found;
  const std::string name = d.properties.deviceName;
  require(d.properties.apiVersion >= VK_API_VERSION_1_1, ErrorCode::backend_unavailable,
          "device " + name + " supports only Vulkan 1.0; 1.1 or newer is required");
  require(d.fp64, ErrorCode::backend_unavailable,
          "device " + name +
              " has no shaderFloat64 (64-bit floats are required for exact predicates)");
  require(h.enabled_features.shaderFloat64 == VK_TRUE, ErrorCode::backend_unavailable,
          "DeviceHandles::enabled_features.shaderFloat64 is VK_FALSE: create the device with "
          "shaderFloat64 enabled (device " + name + " supports it) and pass the features it "
          "was created with");

  std::uint32_t families = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(h.physical_device, &families, nullptr);
  std::vector<VkQueueFamilyProperties> family(families);
  vkGetPhysicalDeviceQueueFamilyProperties(h.physical_device, &families, family.data());
  require(h.queue_family < families, ErrorCode::invalid_argument,
          "queue_family " + std::to_string(h.queue_family) + " does not exist (device " + name +
              " has " + std::to_string(families) + ")");
  require((family[h.queue_family].queueFlags & VK_QUEUE_COMPUTE_BIT) != 0,
          ErrorCode::invalid_argument,
          "queue_family " + std::to_string(h.queue_family) + " of device " + name +
              " does not support compute");
  d.queue_family = h.queue_family;
  d.has_compute_queue = true;
  d.timestamp_bits = family[h.queue_family].timestampValidBits;

  const VkPhysicalDeviceLimits& limits = d.properties.limits;
  auto limit = [&](std::uint32_t have, std::uint32_t need, const char* what) {
    require(have >= need, ErrorCode::backend_unavailable,
            "device " + name + ": " + what + " is " + std::to_string(have) +
                "; Expanse's kernels need " + std::to_string(need));
  };
  limit(limits.maxPerStageDescriptorStorageBuffers, kernel_storage_buffers,
        "maxPerStageDescriptorStorageBuffers");
  limit(limits.maxDescriptorSetStorageBuffers, kernel_storage_buffers,
        "maxDescriptorSetStorageBuffers");
  limit(limits.maxBoundDescriptorSets, 1, "maxBoundDescriptorSets");
  limit(limits.maxPushConstantsSize, kernel_push_constant_bytes, "maxPushConstantsSize");
  return d;
}

}  // namespace

std::size_t max_triangles(std::size_t count) noexcept { return count >= 3 ? 2 * count - 5 : 0; }

VkDeviceSize max_index_buffer_bytes(std::size_t count) noexcept {
  return VkDeviceSize(max_triangles(count)) * 3 * sizeof(std::uint32_t);
}

struct Triangulator::Impl {
  Options options;
  std::shared_ptr<vk::Instance> instance;
  std::shared_ptr<vk::Context> context;
  std::unique_ptr<detail::Backend> backend;
  // Copies count points from the application's buffer to the host, through the context's
  // staging ring (its first command is a barrier against all earlier writes on the queue).
  std::vector<Point2> read_points(VkBuffer points, VkDeviceSize offset, std::size_t count) {
    if (count > std::size_t(std::numeric_limits<std::int32_t>::max()))
      throw Error(ErrorCode::too_large,
                  "at most 2^31 - 1 points are supported, got " + std::to_string(count));
    std::vector<Point2> host(count);
    if (count == 0) return host;
    require(points != VK_NULL_HANDLE, ErrorCode::invalid_argument, "the points buffer is null");
    const VkDeviceSize bytes = VkDeviceSize(count) * sizeof(Point2);
    std::lock_guard lock(context->mutex());
    const vk::StagingRing::Download piece{points, offset, host.data(), bytes};
    context->staging().download({&piece, 1});
    return host;
  }

  // Writes the triangles (already known to fit) into the application's index buffer, through
  // the staging ring; returns when the copies are done (each chunk ends with a barrier that
  // makes them visible to everything submitted later to the queue, index reads included).
  void write_indices(const std::vector<Triangle>& triangles, VkBuffer indices,
                     VkDeviceSize indices_offset) {
    if (triangles.empty()) return;
    static_assert(sizeof(Triangle) == 3 * sizeof(std::uint32_t));
    const VkDeviceSize bytes = VkDeviceSize(triangles.size()) * sizeof(Triangle);
    std::lock_guard lock(context->mutex());
    // Non-negative int32 = uint32.
    const vk::StagingRing::Upload piece{triangles.data(), indices, indices_offset, bytes};
    context->staging().upload({&piece, 1});
    context->staging().wait_idle();
  }

  Mesh run(VkBuffer points, VkDeviceSize offset, std::size_t count, const Options& run_options) {
    const auto start = Clock::now();
    const std::vector<Point2> host = read_points(points, offset, count);
    const double read_ms = ms_since(start);
    Mesh mesh = detail::run_pipeline(*backend, run_options, host);
    mesh.stats.stages.insert(mesh.stats.stages.begin(), {"vulkan interop: read points", read_ms});
    mesh.stats.total_ms += read_ms;
    return mesh;
  }
};

Triangulator::Triangulator(const DeviceHandles& handles, const Options& options)
    : impl_(std::make_unique<Impl>()) {
  detail::require_exact_arithmetic();
  require(handles.instance != VK_NULL_HANDLE && handles.physical_device != VK_NULL_HANDLE &&
              handles.device != VK_NULL_HANDLE && handles.queue != VK_NULL_HANDLE,
          ErrorCode::invalid_argument,
          "DeviceHandles needs instance, physical_device, device and queue (one is null)");
  impl_->options = options;
  impl_->options.backend = BackendKind::vulkan;
  impl_->instance = std::make_shared<vk::Instance>(handles.instance);
  const vk::PhysicalDevice physical = check_device(*impl_->instance, handles);
  impl_->context =
      std::make_shared<vk::Context>(impl_->instance, physical, handles.device, handles.queue);
  const std::string failure = vk::eft_self_test(*impl_->context);
  require(failure.empty(), ErrorCode::backend_unavailable,
          "device " + impl_->context->name() + " fails the exact-arithmetic self-test: " +
              failure);
  impl_->backend = vk::make_backend_on(impl_->context);
}

Triangulator::~Triangulator() = default;
Triangulator::Triangulator(Triangulator&&) noexcept = default;
Triangulator& Triangulator::operator=(Triangulator&&) noexcept = default;

std::string Triangulator::device_name() const { return impl_->context->name(); }

Mesh Triangulator::triangulate(VkBuffer points, VkDeviceSize offset, std::size_t count) {
  return impl_->run(points, offset, count, impl_->options);
}

IndexBufferResult Triangulator::triangulate_to_index_buffer(VkBuffer points, VkDeviceSize offset,
                                                            std::size_t count, VkBuffer indices,
                                                            VkDeviceSize indices_offset,
                                                            VkDeviceSize indices_capacity_bytes) {
  Options run_options = impl_->options;
  run_options.neighbors = false;  // an index buffer has no use for them
  Mesh mesh = impl_->run(points, offset, count, run_options);
  const std::size_t triangles = mesh.triangles.size();
  const VkDeviceSize needed = VkDeviceSize(triangles) * sizeof(Triangle);
  if (needed > indices_capacity_bytes)
    throw Error(ErrorCode::too_large,
                "Vulkan interop: the index buffer holds " +
                    std::to_string(indices_capacity_bytes) + " bytes but the " +
                    std::to_string(triangles) + " triangles need " + std::to_string(needed) +
                    " bytes (max_index_buffer_bytes(" + std::to_string(count) +
                    ") = " + std::to_string(max_index_buffer_bytes(count)) +
                    " is always enough); nothing was written");
  require(triangles == 0 || indices != VK_NULL_HANDLE, ErrorCode::invalid_argument,
          "the index buffer is null");
  const auto start = Clock::now();
  impl_->write_indices(mesh.triangles, indices, indices_offset);
  const double write_ms = ms_since(start);
  IndexBufferResult result;
  result.triangles = triangles;
  result.bytes_written = needed;
  result.stats = std::move(mesh.stats);
  result.stats.stages.push_back({"vulkan interop: write indices", write_ms});
  result.stats.total_ms += write_ms;
  return result;
}

}  // namespace expanse::vulkan
