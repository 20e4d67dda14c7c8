#pragma once
// Vulkan interop: triangulate points that a graphics application already holds in a VkBuffer on
// its own VkDevice, and get the triangles back as a Mesh or written into its own index buffer.
// Besides cuda_interop.hpp, the only public header that mentions Vulkan types; include it only
// when Expanse was built with its Vulkan backend (it is installed only then, and
// expanse::describe_backends() reports the backend as compiled).
//
// Like Kompute's kp::Manager built from existing handles: the application passes what it has,
// Expanse creates no VkInstance or VkDevice, never destroys the application's objects, and
// creates only its own child objects on the device (pipelines, descriptor pools, a command pool,
// a query pool, buffers and memory), which it destroys with its Triangulator.
//
// Expanse calls Vulkan through the loader it links (libvulkan.so.1), so the handles must come
// from that loader: the usual case, volk included (it opens the same library); not from an ICD
// opened directly.
//
// For now the points are read back to the host: validation, duplicate merging, the hull and the
// seam stage are host-side in every backend today (as in expanse::cuda::triangulate_device),
// and the front growth then runs on the application's device and queue.
#include <vulkan/vulkan.h>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

#include "expanse/mesh.hpp"
#include "expanse/options.hpp"

namespace expanse::vulkan {

/// The application's Vulkan objects that Expanse works with. All are borrowed: they must
/// outlive the Triangulator made from them, which never destroys them.
struct DeviceHandles {
  /// Created with VkApplicationInfo::apiVersion >= VK_API_VERSION_1_1.
  VkInstance instance = VK_NULL_HANDLE;
  /// A physical device of `instance` with Vulkan >= 1.1 and shaderFloat64.
  VkPhysicalDevice physical_device = VK_NULL_HANDLE;
  /// Created from physical_device with shaderFloat64 enabled.
  VkDevice device = VK_NULL_HANDLE;
  /// A queue of `device` from family queue_family, which must support VK_QUEUE_COMPUTE_BIT.
  VkQueue queue = VK_NULL_HANDLE;
  std::uint32_t queue_family = 0;
  /// The features `device` was created with (VkDeviceCreateInfo::pEnabledFeatures, or the
  /// VkPhysicalDeviceFeatures2::features in its pNext chain). Vulkan cannot be asked what a
  /// device enabled, so Expanse checks shaderFloat64 here instead of failing in a shader.
  VkPhysicalDeviceFeatures enabled_features{};
};

/// What triangulate_to_index_buffer wrote.
struct IndexBufferResult {
  std::size_t triangles = 0;       ///< triangles written: 3 * triangles uint32 indices
  VkDeviceSize bytes_written = 0;  ///< 12 * triangles, from indices_offset on
  Stats stats;                     ///< as Mesh::stats, plus the interop's read and write stages
};

/// Upper bound on the triangles of `count` points: 2 * count - 5 for count >= 3, else 0 (the
/// exact count, 2 * sites - hull sites - 2, is only known after triangulating).
std::size_t max_triangles(std::size_t count) noexcept;

/// Index buffer capacity, in bytes, that is always enough for `count` points:
/// 3 * sizeof(std::uint32_t) * max_triangles(count).
VkDeviceSize max_index_buffer_bytes(std::size_t count) noexcept;

/// Triangulates on the application's device. Not thread-safe: one per thread, or serialise the
/// calls. Keeps its pipelines and staging memory alive across calls.
///
/// Synchronisation contract of every call that takes a VkBuffer:
///  - Expanse records its own command buffers, submits them to handles.queue and waits for
///    them (a fence) before returning; nothing of Expanse is in flight after a call returns or
///    throws. Vulkan requires the queue to be externally synchronised: the application must not
///    use handles.queue from another thread during a call.
///  - Reading the points: the application's writes to them must be finished and visible to a
///    transfer read on handles.queue. Host writes made before the call qualify (non-coherent
///    memory flushed), and so do device writes submitted earlier to handles.queue: Expanse's
///    first command is a memory barrier against all earlier work on that queue. Device writes on
///    another queue need the application's own synchronisation (e.g. it waited for them).
///  - Writing the indices: when the call returns, the copy into the application's buffer is
///    complete, and a memory barrier makes it visible to every later command on handles.queue
///    (index reads by vkCmdDrawIndexed included).
///  - Buffers created with VK_SHARING_MODE_EXCLUSIVE must be owned by handles.queue_family;
///    ownership transfers from or to other families are the application's.
class Triangulator {
 public:
  /// Checks the handles and the device, compiles the pipelines and runs the exact-arithmetic
  /// self-test on handles.queue (a small submission, waited for).
  /// Preconditions: as DeviceHandles states. Throws Error(invalid_argument) for a null handle,
  /// a physical device that is not one of the instance's, or a queue family out of range or
  /// without compute; Error(backend_unavailable) when the device cannot run Expanse (Vulkan
  /// < 1.1, no shaderFloat64 support, shaderFloat64 not in enabled_features, limits below what
  /// the kernels need, or a failed self-test); Error(device_error) for a failed Vulkan call
  /// (native_code() is the VkResult). options.backend and options.device are ignored;
  /// options.layout and options.neighbors apply as in expanse::triangulate.
  explicit Triangulator(const DeviceHandles& handles, const Options& options = {});
  ~Triangulator();
  Triangulator(Triangulator&&) noexcept;
  Triangulator& operator=(Triangulator&&) noexcept;
  Triangulator(const Triangulator&) = delete;
  Triangulator& operator=(const Triangulator&) = delete;

  /// Delaunay triangulation of `count` points stored at `offset` in `points` as interleaved
  /// (x, y) doubles (the layout of an array of expanse::Point2): the same Mesh, triangle for
  /// triangle, as expanse::triangulate on those points.
  /// Preconditions: points was created on handles.device with VK_BUFFER_USAGE_TRANSFER_SRC_BIT
  /// and holds at least offset + 16 * count bytes, written as the contract above says;
  /// coordinates finite; count < 2^31. count == 0 reads nothing (points may then be null).
  /// Throws like expanse::triangulate: Error(invalid_input) naming the first NaN/Inf point,
  /// Error(too_large) when the input does not fit the device, Error(device_error).
  Mesh triangulate(VkBuffer points, VkDeviceSize offset, std::size_t count);

  /// Triangulates as triangulate() does and writes the triangles into `indices` as a
  /// VK_INDEX_TYPE_UINT32 triangle list: counter-clockwise (y up), three indices into the
  /// application's point array per triangle, a group of equal points represented by its first
  /// occurrence (as Mesh::triangles). Returns how many triangles were written, from
  /// indices_offset on; fewer than three distinct points, or all collinear, write nothing.
  /// Preconditions: as triangulate() for the points; indices was created on handles.device with
  /// VK_BUFFER_USAGE_TRANSFER_DST_BIT and holds at least indices_offset +
  /// indices_capacity_bytes bytes. max_index_buffer_bytes(count) is always enough.
  /// Throws Error(too_large), with the bytes needed in the message, when the triangles do not
  /// fit indices_capacity_bytes; then, and for every other error (NaN/Inf included), nothing
  /// has been written into `indices` (the copy into it is the last step, made only once the
  /// whole mesh is known and fits; only a device lost during that copy can leave it partial).
  IndexBufferResult triangulate_to_index_buffer(VkBuffer points, VkDeviceSize offset,
                                                std::size_t count, VkBuffer indices,
                                                VkDeviceSize indices_offset,
                                                VkDeviceSize indices_capacity_bytes);

  /// The device's name (VkPhysicalDeviceProperties::deviceName).
  std::string device_name() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace expanse::vulkan
