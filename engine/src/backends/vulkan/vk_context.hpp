#pragma once
// Vulkan plumbing for the compute backend: one owner of instance/device/queue (Context) that
// creates everything else (Buffer, Kernel) and records/submits work (Recording).
//
// Ownership follows Kompute: Context is non-copyable and outlives what it creates; it either
// owns its VkInstance/VkDevice or borrows ones the host application already has. Every VkResult
// goes through check(), which throws expanse::Error(device_error) keeping the native code.
#include <vulkan/vulkan.h>

#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <vector>

#include "expanse/error.hpp"
#include "expanse/triangulate.hpp"

namespace expanse::detail::vk {

/// Throws Error(device_error, "<what>: <VkResult name>", result) unless result is VK_SUCCESS.
void check(VkResult result, const char* what);
const char* result_name(VkResult result);

/// What we learned about one physical device, in selection order.
struct PhysicalDevice {
  VkPhysicalDevice handle = VK_NULL_HANDLE;
  VkPhysicalDeviceProperties properties{};
  std::uint32_t queue_family = 0;
  bool has_compute_queue = false;
  bool fp64 = false;
  std::uint32_t subgroup_size = 0;
  std::uint32_t timestamp_bits = 0;
  VkDeviceSize max_allocation = 0;
  std::string unusable;  ///< empty when usable; else why not (e.g. no shaderFloat64)
  DeviceDescription describe(int index) const;
};

/// The VkInstance (+ validation messenger when EXPANSE_VULKAN_VALIDATION=1).
class Instance {
 public:
  /// Throws Error(backend_unavailable) when no Vulkan loader/driver can make an instance.
  Instance();
  /// Borrows an instance the application created; it is not destroyed here.
  explicit Instance(VkInstance borrowed);
  ~Instance();
  Instance(const Instance&) = delete;
  Instance& operator=(const Instance&) = delete;

  VkInstance handle() const { return instance_; }
  /// Physical devices ordered discrete, integrated, virtual, CPU (lavapipe), other.
  const std::vector<PhysicalDevice>& devices() const { return devices_; }
  bool validation() const { return validation_; }
  /// Validation messages so far (warnings and errors); any is a failure.
  std::size_t message_count() const { return messages_.load(); }
  std::string first_message() const;
  /// Throws Error(device_error) if the validation layer reported anything since `since`.
  void throw_if_messages(std::size_t since) const;

 private:
  void enumerate();
  void release();
  static VKAPI_ATTR VkBool32 VKAPI_CALL on_message(VkDebugUtilsMessageSeverityFlagBitsEXT,
                                                   VkDebugUtilsMessageTypeFlagsEXT,
                                                   const VkDebugUtilsMessengerCallbackDataEXT*,
                                                   void*);
  VkInstance instance_ = VK_NULL_HANDLE;
  bool owned_ = true;
  bool validation_ = false;
  VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
  std::vector<PhysicalDevice> devices_;
  std::atomic<std::size_t> messages_{0};
  mutable std::mutex message_mutex_;
  std::string first_message_;
};

class Context;

/// A storage buffer in device memory, or a host-visible staging buffer.
class Buffer {
 public:
  Buffer(Context& context, VkDeviceSize bytes, bool host_visible);
  ~Buffer();
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;
  VkBuffer handle() const { return buffer_; }
  VkDeviceSize size() const { return size_; }
  /// Host pointer for staging buffers (persistently mapped), nullptr otherwise.
  void* mapped() const { return mapped_; }
  /// Buffers made so far in this process (tests check that repeated calls make none).
  static std::uint64_t made() { return made_.load(); }

 private:
  Context& context_;
  VkBuffer buffer_ = VK_NULL_HANDLE;
  VkDeviceMemory memory_ = VK_NULL_HANDLE;
  VkDeviceSize size_ = 0;
  void* mapped_ = nullptr;
  static std::atomic<std::uint64_t> made_;
};

/// A typed view of a Buffer, read in shaders with texelFetch (a uniform texel buffer): on
/// lavapipe a texel fetch is a vector gather, cheaper than a storage-buffer load.
class TexelView {
 public:
  /// The first `bytes` of `buffer` as texels of `format`.
  TexelView(Context& context, const Buffer& buffer, VkFormat format, VkDeviceSize bytes);
  ~TexelView();
  TexelView(const TexelView&) = delete;
  TexelView& operator=(const TexelView&) = delete;
  VkBufferView handle() const { return view_; }

 private:
  Context& context_;
  VkBufferView view_ = VK_NULL_HANDLE;
};

/// One compute pipeline: shader module, layouts, a descriptor set of `bindings` storage buffers
/// (or the types in `types`, when given: storage buffers and uniform texel buffers), push
/// constants, and specialization constants by constant_id (0: workgroup size).
class Kernel {
 public:
  Kernel(Context& context, std::span<const std::uint32_t> spirv, std::uint32_t bindings,
         std::uint32_t push_constant_bytes, std::span<const std::uint32_t> specialization,
         std::span<const VkDescriptorType> types = {});
  ~Kernel();
  Kernel(const Kernel&) = delete;
  Kernel& operator=(const Kernel&) = delete;
  /// Points the descriptor set at these buffers (binding i = buffers[i]; for a texel binding,
  /// texels[i], and buffers[i] is ignored). Only between submissions: the set is not in use by
  /// any pending command buffer then.
  void bind(std::span<Buffer* const> buffers, std::span<const TexelView* const> texels = {});
  VkPipeline pipeline() const { return pipeline_; }
  VkPipelineLayout layout() const { return layout_; }
  VkDescriptorSet set() const { return set_; }
  std::uint32_t push_constant_bytes() const { return push_bytes_; }

 private:
  void release();
  Context& context_;
  std::uint32_t bindings_ = 0;
  std::vector<VkDescriptorType> types_;
  std::uint32_t push_bytes_ = 0;
  VkShaderModule module_ = VK_NULL_HANDLE;
  VkDescriptorSetLayout set_layout_ = VK_NULL_HANDLE;
  VkPipelineLayout layout_ = VK_NULL_HANDLE;
  VkPipeline pipeline_ = VK_NULL_HANDLE;
  VkDescriptorPool pool_ = VK_NULL_HANDLE;
  VkDescriptorSet set_ = VK_NULL_HANDLE;
};

/// Buffers a context keeps between calls, by slot (the per-site layout's, see vulkan_backend.cpp),
/// so that repeated triangulations allocate nothing: expanse::triangulate makes a Backend per call
/// on the process-wide context, and allocating its buffers anew each time cost 365 ms at 4096^2
/// on the H100. Used under Context::mutex() only. Bounded: after each call the backend calls
/// trim(), which releases them all when they total more than Context::keep_bytes().
class BufferCache {
 public:
  explicit BufferCache(Context& context) : context_(context) {}
  BufferCache(const BufferCache&) = delete;
  BufferCache& operator=(const BufferCache&) = delete;
  /// The buffer in `slot`, made anew only when it is missing, smaller than `bytes` or of the
  /// other kind (a too-small one is released first: both need not fit at once).
  Buffer& get(std::size_t slot, VkDeviceSize bytes, bool host_visible);
  /// Releases every buffer when together they hold more than `limit` bytes.
  void trim(VkDeviceSize limit);
  void clear();
  VkDeviceSize bytes() const;

 private:
  Context& context_;
  std::vector<std::unique_ptr<Buffer>> slots_;
};

/// A fixed ring of host-visible staging buffers (slots x chunk bytes, 2 x 32 MiB by default)
/// through which uploads and downloads of any size pass, one chunk per submission: the host's
/// copy of one chunk (on all host threads) overlaps the transfer of the next, and host-visible
/// memory stays bounded whatever the input size. Full-size staging (1.1 GB at 4096^2) was
/// allocated per call, within the 365 ms per call that allocating took on the H100 (staging and
/// device buffers together; the split was not measured). Used under Context::mutex() only; made
/// once per context.
class StagingRing {
 public:
  /// Host memory -> a device buffer.
  struct Upload {
    const void* from;
    VkBuffer to;
    VkDeviceSize offset, bytes;
  };
  /// A device buffer -> host memory.
  struct Download {
    VkBuffer from;
    VkDeviceSize offset;
    void* to;
    VkDeviceSize bytes;
  };
  StagingRing(Context& context, VkDeviceSize chunk_bytes, std::uint32_t slots);
  ~StagingRing();
  StagingRing(const StagingRing&) = delete;
  StagingRing& operator=(const StagingRing&) = delete;
  /// Submits the copies, chunk by chunk, and returns once the host sources may be reused (the
  /// last chunks may still be in flight: wait_idle() waits for them). Each chunk ends with a
  /// barrier that makes its writes visible to everything submitted later to the queue.
  void upload(std::span<const Upload> pieces);
  /// Copies into host memory and returns when all of it is there. Each chunk's commands start
  /// with a barrier against every write submitted earlier to the queue.
  void download(std::span<const Download> pieces);
  /// Waits for every chunk in flight.
  void wait_idle();
  VkDeviceSize bytes() const { return chunk_ * VkDeviceSize(slots_.size()); }

 private:
  struct Slot {
    std::unique_ptr<Buffer> buffer;
    VkCommandBuffer commands = VK_NULL_HANDLE;
    VkFence fence = VK_NULL_HANDLE;
    bool pending = false;
  };
  void wait(Slot& slot);
  void begin(Slot& slot);
  void submit(Slot& slot);
  void release();
  Context& context_;
  VkDeviceSize chunk_;
  std::vector<Slot> slots_;
  std::size_t next_ = 0;
};

/// One command buffer being recorded; submit() waits for completion and returns the device
/// times between consecutive timestamp() marks.
class Recording {
 public:
  /// timed: the recording writes timestamps (the context's one query pool: a recording that
  /// runs beside a timed one must not be timed).
  explicit Recording(Context& context, bool timed = true);
  ~Recording();
  Recording(const Recording&) = delete;
  Recording& operator=(const Recording&) = delete;

  void copy(const Buffer& from, Buffer& to, VkDeviceSize bytes, VkDeviceSize from_offset = 0,
            VkDeviceSize to_offset = 0);
  void fill(Buffer& buffer, std::uint32_t value);
  void dispatch(const Kernel& kernel, const void* push_constants, std::uint32_t groups);
  /// Makes all earlier transfer/compute writes visible to all later transfer/compute access.
  void barrier();
  /// Makes earlier compute writes visible to later transfer/compute access, and waits for
  /// nothing else: transfers still running from an earlier submission go on beside what follows.
  void barrier_after_compute();
  /// Makes all earlier transfer/compute writes visible to the host (after the fence).
  void barrier_to_host();
  /// The command buffer being recorded, for commands the methods above do not cover.
  VkCommandBuffer commands() const { return commands_; }
  /// Marks a stage boundary; the stage ending here is called `name`.
  void timestamp(std::string name);
  /// Submits, waits, and returns the timed stages (empty when the queue has no timestamps).
  std::vector<StageTime> submit();
  /// Submits and returns at once; wait() waits (from any thread: only the fence is used).
  void submit_only();
  void wait();

 private:
  void release();
  Context& context_;
  VkCommandBuffer commands_ = VK_NULL_HANDLE;
  VkFence fence_ = VK_NULL_HANDLE;
  std::vector<std::string> marks_;
  bool timed_ = true;
  bool submitted_ = false;
};

/// The device owner. Not copyable, not movable: everything it creates refers back to it.
class Context {
 public:
  /// Opens physical device `index` of instance->devices() (-1: the first usable one).
  /// Throws Error(backend_unavailable) with the reason when that device cannot be used.
  Context(std::shared_ptr<Instance> instance, int index);
  /// Borrows a device the application already has. It must have been created with
  /// shaderFloat64 enabled and a compute-capable queue family `queue_family`.
  Context(std::shared_ptr<Instance> instance, VkPhysicalDevice physical, VkDevice device,
          std::uint32_t queue_family);
  /// Borrows a device and one of its queues (any index of physical.queue_family) that the
  /// application already has; physical describes that family (queue_family, timestamp_bits).
  /// The caller has checked the device (see expanse/vulkan_interop.hpp). Nothing is waited on
  /// at destruction: every submission of Expanse is waited for before it returns.
  Context(std::shared_ptr<Instance> instance, const PhysicalDevice& physical, VkDevice device,
          VkQueue queue);
  ~Context();
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

  VkDevice device() const { return device_; }
  VkQueue queue() const { return queue_; }
  /// Whether the application lent the device (vulkan_interop.hpp).
  bool borrowed() const { return !owned_; }
  VkCommandPool command_pool() const { return pool_; }
  VkQueryPool query_pool() const { return queries_; }
  std::uint32_t query_capacity() const { return query_capacity_; }
  const PhysicalDevice& physical() const { return physical_; }
  Instance& instance() const { return *instance_; }
  std::string name() const { return physical_.properties.deviceName; }
  const VkPhysicalDeviceLimits& limits() const { return physical_.properties.limits; }
  /// Largest buffer a single storage binding may cover (min of range and allocation limits).
  VkDeviceSize max_buffer_bytes() const;
  /// Throws Error(too_large) naming `what` if `bytes` exceeds max_buffer_bytes().
  void require_fits(VkDeviceSize bytes, const char* what) const;
  std::uint32_t memory_type(std::uint32_t allowed, VkMemoryPropertyFlags wanted,
                            VkMemoryPropertyFlags fallback) const;
  /// Serialises use of the queue, the command pool, the kernels' descriptor sets, the buffer
  /// cache and the staging ring.
  std::mutex& mutex() { return mutex_; }
  /// Buffers kept between calls (under mutex()).
  BufferCache& buffers() { return *cache_; }
  /// The staging ring (under mutex()), made on first use.
  StagingRing& staging();
  /// Waits for the staging ring's chunks in flight, if it has any (before freeing a buffer).
  void wait_staging();
  /// Most bytes the buffer cache keeps between calls: $EXPANSE_VULKAN_KEEP_MB if set (0: keep
  /// nothing), else a quarter of the largest device-local heap.
  VkDeviceSize keep_bytes() const;

  /// Compiled once per context, by name.
  Kernel& kernel(const std::string& name, std::span<const std::uint32_t> spirv,
                 std::uint32_t bindings, std::uint32_t push_constant_bytes,
                 std::span<const std::uint32_t> specialization,
                 std::span<const VkDescriptorType> types = {});

 private:
  void create_common();
  void release();
  std::shared_ptr<Instance> instance_;
  PhysicalDevice physical_;
  bool owned_ = true;
  VkDevice device_ = VK_NULL_HANDLE;
  VkQueue queue_ = VK_NULL_HANDLE;
  VkCommandPool pool_ = VK_NULL_HANDLE;
  VkQueryPool queries_ = VK_NULL_HANDLE;
  std::uint32_t query_capacity_ = 0;
  VkPhysicalDeviceMemoryProperties memory_{};
  std::mutex mutex_;
  std::vector<std::pair<std::string, std::unique_ptr<Kernel>>> kernels_;
  // Destroyed (in release()) before the device they belong to.
  std::unique_ptr<StagingRing> staging_;
  std::unique_ptr<BufferCache> cache_;
};

}  // namespace expanse::detail::vk
