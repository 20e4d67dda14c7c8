// Vulkan structs are value-initialised from their sType alone ({VK_STRUCTURE_TYPE_...}).
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#include "backends/vulkan/vk_context.hpp"
#include "backends/vulkan/tuning.hpp"

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <sstream>

#include "input/parallel.hpp"

namespace expanse::detail::vk {

const char* result_name(VkResult result) {
  switch (result) {
#define EXPANSE_VK_CASE(r) \
  case r:                  \
    return #r;
    EXPANSE_VK_CASE(VK_SUCCESS)
    EXPANSE_VK_CASE(VK_NOT_READY)
    EXPANSE_VK_CASE(VK_TIMEOUT)
    EXPANSE_VK_CASE(VK_INCOMPLETE)
    EXPANSE_VK_CASE(VK_ERROR_OUT_OF_HOST_MEMORY)
    EXPANSE_VK_CASE(VK_ERROR_OUT_OF_DEVICE_MEMORY)
    EXPANSE_VK_CASE(VK_ERROR_INITIALIZATION_FAILED)
    EXPANSE_VK_CASE(VK_ERROR_DEVICE_LOST)
    EXPANSE_VK_CASE(VK_ERROR_MEMORY_MAP_FAILED)
    EXPANSE_VK_CASE(VK_ERROR_LAYER_NOT_PRESENT)
    EXPANSE_VK_CASE(VK_ERROR_EXTENSION_NOT_PRESENT)
    EXPANSE_VK_CASE(VK_ERROR_FEATURE_NOT_PRESENT)
    EXPANSE_VK_CASE(VK_ERROR_INCOMPATIBLE_DRIVER)
    EXPANSE_VK_CASE(VK_ERROR_TOO_MANY_OBJECTS)
    EXPANSE_VK_CASE(VK_ERROR_FORMAT_NOT_SUPPORTED)
    EXPANSE_VK_CASE(VK_ERROR_FRAGMENTED_POOL)
    EXPANSE_VK_CASE(VK_ERROR_OUT_OF_POOL_MEMORY)
    EXPANSE_VK_CASE(VK_ERROR_UNKNOWN)
#undef EXPANSE_VK_CASE
    default:
      return "VkResult(other)";
  }
}

void check(VkResult result, const char* what) {
  if (result == VK_SUCCESS) return;
  std::ostringstream message;
  message << "Vulkan: " << what << " failed: " << result_name(result) << " (" << int(result) << ")";
  throw Error(ErrorCode::device_error, message.str(), static_cast<std::int64_t>(result));
}

namespace {

int type_rank(VkPhysicalDeviceType type) {
  switch (type) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return 0;
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return 1;
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return 2;
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return 3;
    default: return 4;
  }
}

const char* type_name(VkPhysicalDeviceType type) {
  switch (type) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return "discrete";
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return "integrated";
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return "virtual";
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return "cpu";
    default: return "other";
  }
}

bool validation_requested() { return tuning_from_environment().validation; }

bool has_layer(const char* name) {
  std::uint32_t count = 0;
  if (vkEnumerateInstanceLayerProperties(&count, nullptr) != VK_SUCCESS) return false;
  std::vector<VkLayerProperties> layers(count);
  if (vkEnumerateInstanceLayerProperties(&count, layers.data()) != VK_SUCCESS) return false;
  for (const auto& layer : layers)
    if (std::strcmp(layer.layerName, name) == 0) return true;
  return false;
}

constexpr const char* validation_layer = "VK_LAYER_KHRONOS_validation";

}  // namespace

DeviceDescription PhysicalDevice::describe(int index) const {
  DeviceDescription d;
  d.index = index;
  d.name = properties.deviceName;
  d.type = type_name(properties.deviceType);
  d.fp64 = fp64;
  std::ostringstream details;
  details << "Vulkan " << VK_API_VERSION_MAJOR(properties.apiVersion) << "."
          << VK_API_VERSION_MINOR(properties.apiVersion) << ", subgroup " << subgroup_size
          << ", maxStorageBufferRange " << (properties.limits.maxStorageBufferRange >> 20)
          << " MiB, maxComputeWorkGroupInvocations "
          << properties.limits.maxComputeWorkGroupInvocations << ", timestamps "
          << (timestamp_bits ? "yes" : "no");
  if (!unusable.empty()) details << "; unusable: " << unusable;
  d.details = details.str();
  return d;
}

// ---- Instance ---------------------------------------------------------------------------------

Instance::Instance() {
  validation_ = validation_requested();
  if (validation_ && !has_layer(validation_layer))
    throw Error(ErrorCode::backend_unavailable,
                "Vulkan: EXPANSE_VULKAN_VALIDATION=1 but VK_LAYER_KHRONOS_validation is not "
                "installed");
  VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
  app.pApplicationName = "expanse";
  app.pEngineName = "expanse";
  app.apiVersion = VK_API_VERSION_1_2;

  VkDebugUtilsMessengerCreateInfoEXT messenger{
      VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
  messenger.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                              VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
  messenger.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                          VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                          VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
  messenger.pfnUserCallback = &Instance::on_message;
  messenger.pUserData = this;

  std::vector<const char*> layers, extensions;
  VkInstanceCreateInfo info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  info.pApplicationInfo = &app;
  if (validation_) {
    layers.push_back(validation_layer);
    extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
    info.pNext = &messenger;  // also watches instance creation and destruction
  }
  info.enabledLayerCount = static_cast<std::uint32_t>(layers.size());
  info.ppEnabledLayerNames = layers.data();
  info.enabledExtensionCount = static_cast<std::uint32_t>(extensions.size());
  info.ppEnabledExtensionNames = extensions.data();
  const VkResult result = vkCreateInstance(&info, nullptr, &instance_);
  if (result == VK_ERROR_INCOMPATIBLE_DRIVER || result == VK_ERROR_INITIALIZATION_FAILED ||
      result == VK_ERROR_LAYER_NOT_PRESENT || result == VK_ERROR_EXTENSION_NOT_PRESENT)
    throw Error(ErrorCode::backend_unavailable,
                std::string("Vulkan: no usable instance (") + result_name(result) + ")",
                static_cast<std::int64_t>(result));
  check(result, "vkCreateInstance");
  if (validation_) {
    auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance_, "vkCreateDebugUtilsMessengerEXT"));
    if (create == nullptr) {
      vkDestroyInstance(instance_, nullptr);
      throw Error(ErrorCode::backend_unavailable, "Vulkan: VK_EXT_debug_utils unavailable");
    }
    const VkResult r = create(instance_, &messenger, nullptr, &messenger_);
    if (r != VK_SUCCESS) {
      vkDestroyInstance(instance_, nullptr);
      check(r, "vkCreateDebugUtilsMessengerEXT");
    }
  }
  try {
    enumerate();
  } catch (...) {
    release();
    throw;
  }
}

Instance::Instance(VkInstance borrowed) : instance_(borrowed), owned_(false) { enumerate(); }

Instance::~Instance() { release(); }

void Instance::release() {
  if (instance_ == VK_NULL_HANDLE) return;
  if (messenger_ != VK_NULL_HANDLE) {
    auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance_, "vkDestroyDebugUtilsMessengerEXT"));
    if (destroy) destroy(instance_, messenger_, nullptr);
    messenger_ = VK_NULL_HANDLE;
  }
  if (owned_) vkDestroyInstance(instance_, nullptr);
  instance_ = VK_NULL_HANDLE;
}

VKAPI_ATTR VkBool32 VKAPI_CALL Instance::on_message(
    VkDebugUtilsMessageSeverityFlagBitsEXT, VkDebugUtilsMessageTypeFlagsEXT,
    const VkDebugUtilsMessengerCallbackDataEXT* data, void* user) {
  auto* self = static_cast<Instance*>(user);
  if (self->messages_.fetch_add(1) == 0) {
    std::lock_guard lock(self->message_mutex_);
    self->first_message_ = data && data->pMessage ? data->pMessage : "(no text)";
  }
  return VK_FALSE;
}

std::string Instance::first_message() const {
  std::lock_guard lock(message_mutex_);
  return first_message_;
}

void Instance::throw_if_messages(std::size_t since) const {
  const std::size_t now = message_count();
  if (now == since) return;
  throw Error(ErrorCode::device_error, "Vulkan validation layer reported " +
                                           std::to_string(now - since) +
                                           " message(s); first: " + first_message());
}

void Instance::enumerate() {
  std::uint32_t count = 0;
  check(vkEnumeratePhysicalDevices(instance_, &count, nullptr), "vkEnumeratePhysicalDevices");
  std::vector<VkPhysicalDevice> handles(count);
  check(vkEnumeratePhysicalDevices(instance_, &count, handles.data()),
        "vkEnumeratePhysicalDevices");
  for (VkPhysicalDevice handle : handles) {
    PhysicalDevice d;
    d.handle = handle;
    VkPhysicalDeviceSubgroupProperties subgroup{
        VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_PROPERTIES};
    VkPhysicalDeviceMaintenance3Properties maintenance3{
        VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MAINTENANCE_3_PROPERTIES};
    subgroup.pNext = &maintenance3;
    VkPhysicalDeviceProperties2 properties{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
    properties.pNext = &subgroup;
    vkGetPhysicalDeviceProperties2(handle, &properties);
    d.properties = properties.properties;
    d.subgroup_size = subgroup.subgroupSize;
    d.max_allocation = maintenance3.maxMemoryAllocationSize;
    VkPhysicalDeviceFeatures features{};
    vkGetPhysicalDeviceFeatures(handle, &features);
    d.fp64 = features.shaderFloat64 == VK_TRUE;

    std::uint32_t families = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(handle, &families, nullptr);
    std::vector<VkQueueFamilyProperties> family(families);
    vkGetPhysicalDeviceQueueFamilyProperties(handle, &families, family.data());
    // Prefer a compute-only family (async compute engines), else any with compute.
    int chosen = -1;
    for (std::uint32_t i = 0; i < families; ++i) {
      if (!(family[i].queueFlags & VK_QUEUE_COMPUTE_BIT)) continue;
      if (chosen < 0 || !(family[i].queueFlags & VK_QUEUE_GRAPHICS_BIT)) chosen = int(i);
      if (!(family[i].queueFlags & VK_QUEUE_GRAPHICS_BIT)) break;
    }
    if (chosen >= 0) {
      d.has_compute_queue = true;
      d.queue_family = std::uint32_t(chosen);
      d.timestamp_bits = family[chosen].timestampValidBits;
    }
    if (d.properties.apiVersion < VK_API_VERSION_1_1)
      d.unusable = "Vulkan 1.1 or newer required";
    else if (!d.fp64)
      d.unusable = "no shaderFloat64 (64-bit floats are required for exact predicates)";
    else if (!d.has_compute_queue)
      d.unusable = "no compute queue";
    devices_.push_back(d);
  }
  std::stable_sort(devices_.begin(), devices_.end(), [](const auto& a, const auto& b) {
    return type_rank(a.properties.deviceType) < type_rank(b.properties.deviceType);
  });
}

// ---- Context ----------------------------------------------------------------------------------

Context::Context(std::shared_ptr<Instance> instance, int index) : instance_(std::move(instance)) {
  const auto& devices = instance_->devices();
  if (devices.empty())
    throw Error(ErrorCode::backend_unavailable, "Vulkan: no physical devices");
  if (index < 0) {
    std::string reasons;
    for (std::size_t i = 0; i < devices.size(); ++i) {
      if (devices[i].unusable.empty()) {
        index = int(i);
        break;
      }
      reasons += std::string(i ? "; " : "") + devices[i].properties.deviceName + ": " +
                 devices[i].unusable;
    }
    if (index < 0)
      throw Error(ErrorCode::backend_unavailable, "Vulkan: no usable device (" + reasons + ")");
  }
  if (index >= int(devices.size()))
    throw Error(ErrorCode::backend_unavailable,
                "Vulkan: device " + std::to_string(index) + " does not exist (" +
                    std::to_string(devices.size()) + " device(s))");
  physical_ = devices[std::size_t(index)];
  if (!physical_.unusable.empty())
    throw Error(ErrorCode::backend_unavailable,
                std::string("Vulkan: device ") + physical_.properties.deviceName +
                    " is unusable: " + physical_.unusable);

  const float priority = 1.0f;
  VkDeviceQueueCreateInfo queue{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
  queue.queueFamilyIndex = physical_.queue_family;
  queue.queueCount = 1;
  queue.pQueuePriorities = &priority;
  VkPhysicalDeviceFeatures features{};
  features.shaderFloat64 = VK_TRUE;
  VkDeviceCreateInfo info{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
  info.queueCreateInfoCount = 1;
  info.pQueueCreateInfos = &queue;
  info.pEnabledFeatures = &features;
  check(vkCreateDevice(physical_.handle, &info, nullptr, &device_), "vkCreateDevice");
  try {
    create_common();
  } catch (...) {
    release();
    throw;
  }
}

Context::Context(std::shared_ptr<Instance> instance, VkPhysicalDevice physical, VkDevice device,
                 std::uint32_t queue_family)
    : instance_(std::move(instance)), owned_(false), device_(device) {
  bool found = false;
  for (const auto& d : instance_->devices())
    if (d.handle == physical) {
      physical_ = d;
      found = true;
    }
  if (!found) throw Error(ErrorCode::invalid_argument, "Vulkan: unknown physical device");
  if (!physical_.fp64)
    throw Error(ErrorCode::backend_unavailable, "Vulkan: borrowed device lacks shaderFloat64");
  physical_.queue_family = queue_family;
  create_common();
}

Context::Context(std::shared_ptr<Instance> instance, const PhysicalDevice& physical,
                 VkDevice device, VkQueue queue)
    : instance_(std::move(instance)), physical_(physical), owned_(false), device_(device),
      queue_(queue) {
  try {
    create_common();
  } catch (...) {
    release();
    throw;
  }
}

void Context::create_common() {
  cache_ = std::make_unique<BufferCache>(*this);
  if (queue_ == VK_NULL_HANDLE) vkGetDeviceQueue(device_, physical_.queue_family, 0, &queue_);
  vkGetPhysicalDeviceMemoryProperties(physical_.handle, &memory_);
  VkCommandPoolCreateInfo pool{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
  pool.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  pool.queueFamilyIndex = physical_.queue_family;
  check(vkCreateCommandPool(device_, &pool, nullptr, &pool_), "vkCreateCommandPool");
  if (physical_.timestamp_bits > 0) {
    query_capacity_ = 32;
    VkQueryPoolCreateInfo query{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
    query.queryType = VK_QUERY_TYPE_TIMESTAMP;
    query.queryCount = query_capacity_;
    check(vkCreateQueryPool(device_, &query, nullptr, &queries_), "vkCreateQueryPool");
  }
}

Context::~Context() { release(); }

void Context::release() {
  if (device_ == VK_NULL_HANDLE) return;
  // A borrowed device's queues belong to the application (and must be externally
  // synchronised): nothing of ours is in flight there, so do not touch them.
  if (owned_) vkDeviceWaitIdle(device_);
  staging_.reset();  // waits for its chunks in flight; frees its command buffers
  cache_.reset();
  kernels_.clear();
  if (queries_ != VK_NULL_HANDLE) vkDestroyQueryPool(device_, queries_, nullptr);
  if (pool_ != VK_NULL_HANDLE) vkDestroyCommandPool(device_, pool_, nullptr);
  queries_ = VK_NULL_HANDLE;
  pool_ = VK_NULL_HANDLE;
  if (owned_) vkDestroyDevice(device_, nullptr);
  device_ = VK_NULL_HANDLE;
}

VkDeviceSize Context::max_buffer_bytes() const {
  VkDeviceSize limit = limits().maxStorageBufferRange;
  if (physical_.max_allocation > 0) limit = std::min(limit, physical_.max_allocation);
  return limit;
}

void Context::require_fits(VkDeviceSize bytes, const char* what) const {
  if (bytes <= max_buffer_bytes()) return;
  throw Error(ErrorCode::too_large,
              std::string("Vulkan: ") + what + " needs " + std::to_string(bytes >> 20) +
                  " MiB in one storage buffer; device " + name() + " allows " +
                  std::to_string(max_buffer_bytes() >> 20) +
                  " MiB (maxStorageBufferRange/maxMemoryAllocationSize)");
}

std::uint32_t Context::memory_type(std::uint32_t allowed, VkMemoryPropertyFlags wanted,
                                   VkMemoryPropertyFlags fallback) const {
  for (VkMemoryPropertyFlags flags : {wanted, fallback})
    for (std::uint32_t i = 0; i < memory_.memoryTypeCount; ++i)
      if ((allowed & (1u << i)) && (memory_.memoryTypes[i].propertyFlags & flags) == flags)
        return i;
  throw Error(ErrorCode::device_error, "Vulkan: no suitable memory type", 0);
}

Kernel& Context::kernel(const std::string& name, std::span<const std::uint32_t> spirv,
                        std::uint32_t bindings, std::uint32_t push_constant_bytes,
                        std::span<const std::uint32_t> specialization,
                        std::span<const VkDescriptorType> types) {
  std::string key = name;
  for (std::uint32_t v : specialization) {
    key += '/';
    key += std::to_string(v);
  }
  for (auto& [k, kernel] : kernels_)
    if (k == key) return *kernel;
  kernels_.emplace_back(key, std::make_unique<Kernel>(*this, spirv, bindings, push_constant_bytes,
                                                      specialization, types));
  return *kernels_.back().second;
}

StagingRing& Context::staging() {
  if (!staging_) {
    // 2 x 32 MiB by default, as the CUDA backend's pinned staging (Tuning::staging_mb).
    const VkDeviceSize chunk = VkDeviceSize(tuning_from_environment().staging_mb) << 20;
    staging_ = std::make_unique<StagingRing>(*this, chunk, 2);
  }
  return *staging_;
}

void Context::wait_staging() {
  if (staging_) staging_->wait_idle();
}

VkDeviceSize Context::keep_bytes() const {
  if (const std::int64_t keep = tuning_from_environment().keep_mb; keep >= 0) return VkDeviceSize(keep) << 20;
  VkDeviceSize heap = 0;
  for (std::uint32_t i = 0; i < memory_.memoryHeapCount; ++i)
    if (memory_.memoryHeaps[i].flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT)
      heap = std::max(heap, memory_.memoryHeaps[i].size);
  return heap / 4;
}

// ---- BufferCache ------------------------------------------------------------------------------

Buffer& BufferCache::get(std::size_t slot, VkDeviceSize bytes, bool host_visible) {
  if (slot >= slots_.size()) slots_.resize(slot + 1);
  std::unique_ptr<Buffer>& kept = slots_[slot];
  if (!kept || kept->size() < bytes || (kept->mapped() != nullptr) != host_visible) {
    if (kept) context_.wait_staging();  // no copy may still be reading or writing it
    kept.reset();  // the old one goes first: both need not fit at once
    kept = std::make_unique<Buffer>(context_, bytes, host_visible);
  }
  return *kept;
}

VkDeviceSize BufferCache::bytes() const {
  VkDeviceSize total = 0;
  for (const auto& b : slots_)
    if (b) total += b->size();
  return total;
}

void BufferCache::trim(VkDeviceSize limit) {
  if (bytes() > limit) clear();
}

void BufferCache::clear() {
  context_.wait_staging();
  slots_.clear();
}

// ---- StagingRing ------------------------------------------------------------------------------

namespace {

// memcpy in one sequential stream per host thread (1 MiB at least each).
void copy_on_threads(void* to, const void* from, std::size_t bytes) {
  detail::parallel_chunks(bytes, detail::chunk_count(bytes, std::size_t(1) << 20),
                          [&](std::size_t, std::size_t begin, std::size_t end) {
                            std::memcpy(static_cast<char*>(to) + begin,
                                        static_cast<const char*>(from) + begin, end - begin);
                          });
}

// The pieces cut into chunks of at most `chunk` bytes, packed: (piece, offset in the piece,
// offset in the chunk, bytes) per part.
struct Part {
  std::size_t piece;
  VkDeviceSize at, ring_at, bytes;
};
template <class Piece>
std::vector<std::vector<Part>> plan_chunks(std::span<const Piece> pieces, VkDeviceSize chunk) {
  std::vector<std::vector<Part>> chunks;
  VkDeviceSize used = chunk;  // the current chunk is full: start a new one
  for (std::size_t p = 0; p < pieces.size(); ++p)
    for (VkDeviceSize at = 0; at < pieces[p].bytes;) {
      if (used == chunk) {
        chunks.emplace_back();
        used = 0;
      }
      const VkDeviceSize bytes = std::min(chunk - used, pieces[p].bytes - at);
      chunks.back().push_back({p, at, used, bytes});
      at += bytes;
      used += bytes;
    }
  return chunks;
}

}  // namespace

StagingRing::StagingRing(Context& context, VkDeviceSize chunk_bytes, std::uint32_t slots)
    : context_(context), chunk_(chunk_bytes), slots_(std::max(2u, slots)) {
  try {
    for (Slot& slot : slots_) {
      slot.buffer = std::make_unique<Buffer>(context, chunk_, true);
      VkCommandBufferAllocateInfo allocate{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
      allocate.commandPool = context.command_pool();
      allocate.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
      allocate.commandBufferCount = 1;
      check(vkAllocateCommandBuffers(context.device(), &allocate, &slot.commands),
            "vkAllocateCommandBuffers");
      VkFenceCreateInfo fence{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
      check(vkCreateFence(context.device(), &fence, nullptr, &slot.fence), "vkCreateFence");
    }
  } catch (...) {
    release();
    throw;
  }
}

StagingRing::~StagingRing() { release(); }

void StagingRing::release() {
  for (Slot& slot : slots_) {
    if (slot.pending && slot.fence != VK_NULL_HANDLE)
      vkWaitForFences(context_.device(), 1, &slot.fence, VK_TRUE, UINT64_MAX);
    slot.pending = false;
    if (slot.fence != VK_NULL_HANDLE) vkDestroyFence(context_.device(), slot.fence, nullptr);
    if (slot.commands != VK_NULL_HANDLE)
      vkFreeCommandBuffers(context_.device(), context_.command_pool(), 1, &slot.commands);
    slot.fence = VK_NULL_HANDLE;
    slot.commands = VK_NULL_HANDLE;
    slot.buffer.reset();
  }
}

void StagingRing::wait(Slot& slot) {
  if (!slot.pending) return;
  for (;;) {
    const VkResult result =
        vkWaitForFences(context_.device(), 1, &slot.fence, VK_TRUE, 10'000'000'000ull);
    if (result == VK_TIMEOUT) continue;
    check(result, "vkWaitForFences");
    break;
  }
  slot.pending = false;
}

void StagingRing::wait_idle() {
  for (Slot& slot : slots_) wait(slot);
}

void StagingRing::begin(Slot& slot) {
  wait(slot);
  check(vkResetFences(context_.device(), 1, &slot.fence), "vkResetFences");
  VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  check(vkBeginCommandBuffer(slot.commands, &begin), "vkBeginCommandBuffer");
}

void StagingRing::submit(Slot& slot) {
  check(vkEndCommandBuffer(slot.commands), "vkEndCommandBuffer");
  VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  submit.commandBufferCount = 1;
  submit.pCommandBuffers = &slot.commands;
  check(vkQueueSubmit(context_.queue(), 1, &submit, slot.fence), "vkQueueSubmit");
  slot.pending = true;
}

void StagingRing::upload(std::span<const Upload> pieces) {
  for (const auto& chunk : plan_chunks(pieces, chunk_)) {
    Slot& slot = slots_[next_];
    next_ = (next_ + 1) % slots_.size();
    begin(slot);  // waits for the copy that last read this slot
    char* ring = static_cast<char*>(slot.buffer->mapped());
    for (const Part& part : chunk) {
      const Upload& piece = pieces[part.piece];
      copy_on_threads(ring + part.ring_at, static_cast<const char*>(piece.from) + part.at,
                      part.bytes);
      const VkBufferCopy region{part.ring_at, piece.offset + part.at, part.bytes};
      vkCmdCopyBuffer(slot.commands, slot.buffer->handle(), piece.to, 1, &region);
    }
    // Visible to everything submitted later to the queue (an interop application's index
    // reads too).
    VkMemoryBarrier after{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    after.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    after.dstAccessMask = VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_MEMORY_WRITE_BIT;
    vkCmdPipelineBarrier(slot.commands, VK_PIPELINE_STAGE_TRANSFER_BIT,
                         VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, 0, 1, &after, 0, nullptr, 0, nullptr);
    submit(slot);
  }
}

void StagingRing::download(std::span<const Download> pieces) {
  const auto chunks = plan_chunks(pieces, chunk_);
  const std::size_t base = next_, count = slots_.size();
  auto slot_of = [&](std::size_t c) -> Slot& { return slots_[(base + c) % count]; };
  std::size_t issued = 0;
  for (std::size_t c = 0; c < chunks.size(); ++c) {
    // Up to `count` chunks in flight: the slot of chunk c + count - 1 was drained (chunk c - 1).
    for (; issued < chunks.size() && issued < c + count; ++issued) {
      Slot& slot = slot_of(issued);
      begin(slot);
      // Every write submitted earlier to the queue (an interop application's too), before
      // our reads.
      VkMemoryBarrier before{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
      before.srcAccessMask = VK_ACCESS_MEMORY_WRITE_BIT;
      before.dstAccessMask = VK_ACCESS_TRANSFER_READ_BIT;
      vkCmdPipelineBarrier(slot.commands, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT,
                           VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 1, &before, 0, nullptr, 0, nullptr);
      for (const Part& part : chunks[issued]) {
        const Download& piece = pieces[part.piece];
        const VkBufferCopy region{piece.offset + part.at, part.ring_at, part.bytes};
        vkCmdCopyBuffer(slot.commands, piece.from, slot.buffer->handle(), 1, &region);
      }
      VkMemoryBarrier after{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
      after.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
      after.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
      vkCmdPipelineBarrier(slot.commands, VK_PIPELINE_STAGE_TRANSFER_BIT,
                           VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &after, 0, nullptr, 0, nullptr);
      submit(slot);
    }
    Slot& slot = slot_of(c);
    wait(slot);
    const char* ring = static_cast<const char*>(slot.buffer->mapped());
    for (const Part& part : chunks[c]) {
      const Download& piece = pieces[part.piece];
      copy_on_threads(static_cast<char*>(piece.to) + part.at, ring + part.ring_at, part.bytes);
    }
  }
  next_ = (base + chunks.size()) % count;
}

// ---- Buffer -----------------------------------------------------------------------------------

std::atomic<std::uint64_t> Buffer::made_{0};

Buffer::Buffer(Context& context, VkDeviceSize bytes, bool host_visible)
    : context_(context), size_(std::max<VkDeviceSize>(bytes, 16)) {
  if (!host_visible) context.require_fits(size_, "a storage buffer");
  VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  info.size = size_;
  info.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT |
               VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
  info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  check(vkCreateBuffer(context.device(), &info, nullptr, &buffer_), "vkCreateBuffer");
  VkMemoryRequirements requirements;
  vkGetBufferMemoryRequirements(context.device(), buffer_, &requirements);
  VkMemoryAllocateInfo allocate{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  allocate.allocationSize = requirements.size;
  allocate.memoryTypeIndex =
      host_visible
          ? context.memory_type(requirements.memoryTypeBits,
                                VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT |
                                    VK_MEMORY_PROPERTY_HOST_COHERENT_BIT |
                                    VK_MEMORY_PROPERTY_HOST_CACHED_BIT,
                                VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT |
                                    VK_MEMORY_PROPERTY_HOST_COHERENT_BIT)
          : context.memory_type(requirements.memoryTypeBits,
                                VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, 0);
  VkResult result = vkAllocateMemory(context.device(), &allocate, nullptr, &memory_);
  if (result != VK_SUCCESS) {
    vkDestroyBuffer(context.device(), buffer_, nullptr);
    if (result == VK_ERROR_OUT_OF_DEVICE_MEMORY || result == VK_ERROR_OUT_OF_HOST_MEMORY)
      throw Error(ErrorCode::too_large,
                  "Vulkan: out of memory allocating " + std::to_string(size_ >> 20) + " MiB",
                  static_cast<std::int64_t>(result));
    check(result, "vkAllocateMemory");
  }
  result = vkBindBufferMemory(context.device(), buffer_, memory_, 0);
  if (result == VK_SUCCESS && host_visible)
    result = vkMapMemory(context.device(), memory_, 0, VK_WHOLE_SIZE, 0, &mapped_);
  if (result != VK_SUCCESS) {
    vkFreeMemory(context.device(), memory_, nullptr);
    vkDestroyBuffer(context.device(), buffer_, nullptr);
    check(result, host_visible ? "vkMapMemory" : "vkBindBufferMemory");
  }
  made_.fetch_add(1);
}

Buffer::~Buffer() {
  if (mapped_) vkUnmapMemory(context_.device(), memory_);
  vkDestroyBuffer(context_.device(), buffer_, nullptr);
  vkFreeMemory(context_.device(), memory_, nullptr);
}

// ---- TexelView --------------------------------------------------------------------------------

TexelView::TexelView(Context& context, const Buffer& buffer, VkFormat format, VkDeviceSize bytes)
    : context_(context) {
  VkBufferViewCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_VIEW_CREATE_INFO};
  info.buffer = buffer.handle();
  info.format = format;
  info.offset = 0;
  info.range = bytes;
  check(vkCreateBufferView(context.device(), &info, nullptr, &view_), "vkCreateBufferView");
}

TexelView::~TexelView() { vkDestroyBufferView(context_.device(), view_, nullptr); }

// ---- Kernel -----------------------------------------------------------------------------------

Kernel::Kernel(Context& context, std::span<const std::uint32_t> spirv, std::uint32_t bindings,
               std::uint32_t push_constant_bytes, std::span<const std::uint32_t> specialization,
               std::span<const VkDescriptorType> types)
    : context_(context),
      bindings_(bindings),
      types_(types.begin(), types.end()),
      push_bytes_(push_constant_bytes) {
  if (types_.empty()) types_.assign(bindings, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER);
  if (types_.size() != bindings)
    throw Error(ErrorCode::internal, "Vulkan: kernel descriptor types do not match its bindings");
  VkDevice device = context.device();
  // Destroys what was made so far if a later step throws.
  struct Guard {
    Kernel* k;
    bool done = false;
    ~Guard() {
      if (!done) k->release();
    }
  } guard{this};

  VkShaderModuleCreateInfo module{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
  module.codeSize = spirv.size_bytes();
  module.pCode = spirv.data();
  check(vkCreateShaderModule(device, &module, nullptr, &module_), "vkCreateShaderModule");

  std::vector<VkDescriptorSetLayoutBinding> layout_bindings(bindings);
  for (std::uint32_t i = 0; i < bindings; ++i) {
    layout_bindings[i].binding = i;
    layout_bindings[i].descriptorType = types_[i];
    layout_bindings[i].descriptorCount = 1;
    layout_bindings[i].stageFlags = VK_SHADER_STAGE_COMPUTE_BIT;
  }
  VkDescriptorSetLayoutCreateInfo set_layout{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
  set_layout.bindingCount = bindings;
  set_layout.pBindings = layout_bindings.data();
  check(vkCreateDescriptorSetLayout(device, &set_layout, nullptr, &set_layout_),
        "vkCreateDescriptorSetLayout");

  VkPushConstantRange range{VK_SHADER_STAGE_COMPUTE_BIT, 0, push_constant_bytes};
  VkPipelineLayoutCreateInfo layout{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
  layout.setLayoutCount = 1;
  layout.pSetLayouts = &set_layout_;
  layout.pushConstantRangeCount = push_constant_bytes ? 1 : 0;
  layout.pPushConstantRanges = &range;
  check(vkCreatePipelineLayout(device, &layout, nullptr, &layout_), "vkCreatePipelineLayout");

  std::vector<VkSpecializationMapEntry> entries(specialization.size());
  for (std::size_t i = 0; i < specialization.size(); ++i)
    entries[i] = {std::uint32_t(i), std::uint32_t(i * sizeof(std::uint32_t)),
                  sizeof(std::uint32_t)};
  VkSpecializationInfo spec{};
  spec.mapEntryCount = std::uint32_t(entries.size());
  spec.pMapEntries = entries.data();
  spec.dataSize = specialization.size_bytes();
  spec.pData = specialization.data();

  VkComputePipelineCreateInfo pipeline{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
  pipeline.stage.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
  pipeline.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
  pipeline.stage.module = module_;
  pipeline.stage.pName = "main";
  pipeline.stage.pSpecializationInfo = specialization.empty() ? nullptr : &spec;
  pipeline.layout = layout_;
  check(vkCreateComputePipelines(device, VK_NULL_HANDLE, 1, &pipeline, nullptr, &pipeline_),
        "vkCreateComputePipelines");

  std::vector<VkDescriptorPoolSize> sizes;
  for (VkDescriptorType type : types_) {
    auto same = std::find_if(sizes.begin(), sizes.end(), [&](const auto& s) { return s.type == type; });
    if (same == sizes.end()) sizes.push_back({type, 1});
    else ++same->descriptorCount;
  }
  VkDescriptorPoolCreateInfo pool{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
  pool.maxSets = 1;
  pool.poolSizeCount = std::uint32_t(sizes.size());
  pool.pPoolSizes = sizes.data();
  check(vkCreateDescriptorPool(device, &pool, nullptr, &pool_), "vkCreateDescriptorPool");
  VkDescriptorSetAllocateInfo allocate{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
  allocate.descriptorPool = pool_;
  allocate.descriptorSetCount = 1;
  allocate.pSetLayouts = &set_layout_;
  check(vkAllocateDescriptorSets(device, &allocate, &set_), "vkAllocateDescriptorSets");
  guard.done = true;
}

Kernel::~Kernel() { release(); }

void Kernel::release() {
  VkDevice device = context_.device();
  if (pool_) vkDestroyDescriptorPool(device, pool_, nullptr);
  if (pipeline_) vkDestroyPipeline(device, pipeline_, nullptr);
  if (layout_) vkDestroyPipelineLayout(device, layout_, nullptr);
  if (set_layout_) vkDestroyDescriptorSetLayout(device, set_layout_, nullptr);
  if (module_) vkDestroyShaderModule(device, module_, nullptr);
  pool_ = VK_NULL_HANDLE;
  pipeline_ = VK_NULL_HANDLE;
  layout_ = VK_NULL_HANDLE;
  set_layout_ = VK_NULL_HANDLE;
  module_ = VK_NULL_HANDLE;
}

void Kernel::bind(std::span<Buffer* const> buffers, std::span<const TexelView* const> texels) {
  if (buffers.size() != bindings_ || (!texels.empty() && texels.size() != bindings_))
    throw Error(ErrorCode::internal, "Vulkan: kernel bound with the wrong number of buffers");
  std::vector<VkDescriptorBufferInfo> infos(buffers.size());
  std::vector<VkBufferView> views(buffers.size());
  std::vector<VkWriteDescriptorSet> writes(buffers.size());
  for (std::size_t i = 0; i < buffers.size(); ++i) {
    writes[i] = {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    writes[i].dstSet = set_;
    writes[i].dstBinding = std::uint32_t(i);
    writes[i].descriptorCount = 1;
    writes[i].descriptorType = types_[i];
    if (types_[i] == VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER) {
      if (texels.empty() || texels[i] == nullptr)
        throw Error(ErrorCode::internal, "Vulkan: texel binding without a view");
      views[i] = texels[i]->handle();
      writes[i].pTexelBufferView = &views[i];
    } else {
      infos[i] = {buffers[i]->handle(), 0, VK_WHOLE_SIZE};
      writes[i].pBufferInfo = &infos[i];
    }
  }
  vkUpdateDescriptorSets(context_.device(), std::uint32_t(writes.size()), writes.data(), 0,
                         nullptr);
}

// ---- Recording --------------------------------------------------------------------------------

Recording::Recording(Context& context, bool timed) : context_(context), timed_(timed) {
  VkCommandBufferAllocateInfo allocate{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  allocate.commandPool = context.command_pool();
  allocate.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  allocate.commandBufferCount = 1;
  check(vkAllocateCommandBuffers(context.device(), &allocate, &commands_),
        "vkAllocateCommandBuffers");
  VkFenceCreateInfo fence{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  VkResult result = vkCreateFence(context.device(), &fence, nullptr, &fence_);
  if (result != VK_SUCCESS) {
    vkFreeCommandBuffers(context.device(), context.command_pool(), 1, &commands_);
    check(result, "vkCreateFence");
  }
  VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  result = vkBeginCommandBuffer(commands_, &begin);
  if (result != VK_SUCCESS) {
    release();
    check(result, "vkBeginCommandBuffer");
  }
  if (timed_ && context.query_pool() != VK_NULL_HANDLE) {
    vkCmdResetQueryPool(commands_, context.query_pool(), 0, context.query_capacity());
    vkCmdWriteTimestamp(commands_, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, context.query_pool(), 0);
  }
}

Recording::~Recording() { release(); }

void Recording::release() {
  if (fence_ != VK_NULL_HANDLE) {
    // A recording abandoned after submit (an exception) must not free a buffer in flight.
    if (submitted_) vkWaitForFences(context_.device(), 1, &fence_, VK_TRUE, UINT64_MAX);
    vkDestroyFence(context_.device(), fence_, nullptr);
  }
  if (commands_ != VK_NULL_HANDLE)
    vkFreeCommandBuffers(context_.device(), context_.command_pool(), 1, &commands_);
  fence_ = VK_NULL_HANDLE;
  commands_ = VK_NULL_HANDLE;
}

void Recording::copy(const Buffer& from, Buffer& to, VkDeviceSize bytes, VkDeviceSize from_offset,
                     VkDeviceSize to_offset) {
  if (bytes == 0) return;
  VkBufferCopy region{from_offset, to_offset, bytes};
  vkCmdCopyBuffer(commands_, from.handle(), to.handle(), 1, &region);
}

void Recording::fill(Buffer& buffer, std::uint32_t value) {
  vkCmdFillBuffer(commands_, buffer.handle(), 0, VK_WHOLE_SIZE, value);
}

void Recording::dispatch(const Kernel& kernel, const void* push_constants, std::uint32_t groups) {
  if (groups == 0) return;
  vkCmdBindPipeline(commands_, VK_PIPELINE_BIND_POINT_COMPUTE, kernel.pipeline());
  VkDescriptorSet set = kernel.set();
  vkCmdBindDescriptorSets(commands_, VK_PIPELINE_BIND_POINT_COMPUTE, kernel.layout(), 0, 1, &set,
                          0, nullptr);
  if (kernel.push_constant_bytes())
    vkCmdPushConstants(commands_, kernel.layout(), VK_SHADER_STAGE_COMPUTE_BIT, 0,
                       kernel.push_constant_bytes(), push_constants);
  vkCmdDispatch(commands_, groups, 1, 1);
}

void Recording::barrier() {
  VkMemoryBarrier memory{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
  memory.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
  memory.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT |
                         VK_ACCESS_TRANSFER_READ_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
  const VkPipelineStageFlags stages =
      VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT;
  vkCmdPipelineBarrier(commands_, stages, stages, 0, 1, &memory, 0, nullptr, 0, nullptr);
}

void Recording::barrier_after_compute() {
  VkMemoryBarrier memory{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
  memory.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT;
  memory.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT |
                         VK_ACCESS_TRANSFER_READ_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
  vkCmdPipelineBarrier(commands_, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                       VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 1,
                       &memory, 0, nullptr, 0, nullptr);
}

void Recording::barrier_to_host() {
  VkMemoryBarrier memory{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
  memory.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
  memory.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
  vkCmdPipelineBarrier(commands_,
                       VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                       VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &memory, 0, nullptr, 0, nullptr);
}

void Recording::timestamp(std::string name) {
  if (!timed_ || context_.query_pool() == VK_NULL_HANDLE) return;
  if (marks_.size() + 2 > context_.query_capacity()) return;
  marks_.push_back(std::move(name));
  vkCmdWriteTimestamp(commands_, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, context_.query_pool(),
                      std::uint32_t(marks_.size()));
}

void Recording::submit_only() {
  check(vkEndCommandBuffer(commands_), "vkEndCommandBuffer");
  VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  submit.commandBufferCount = 1;
  submit.pCommandBuffers = &commands_;
  check(vkQueueSubmit(context_.queue(), 1, &submit, fence_), "vkQueueSubmit");
  submitted_ = true;
}

void Recording::wait() {
  // Long dispatches (lavapipe, big inputs) can take minutes: wait in slices, never give up.
  for (;;) {
    const VkResult result =
        vkWaitForFences(context_.device(), 1, &fence_, VK_TRUE, 10'000'000'000ull);
    if (result == VK_TIMEOUT) continue;
    check(result, "vkWaitForFences");
    break;
  }
}

std::vector<StageTime> Recording::submit() {
  submit_only();
  wait();
  std::vector<StageTime> stages;
  if (context_.query_pool() != VK_NULL_HANDLE && !marks_.empty()) {
    std::vector<std::uint64_t> ticks(marks_.size() + 1);
    check(vkGetQueryPoolResults(context_.device(), context_.query_pool(), 0,
                                std::uint32_t(ticks.size()), ticks.size() * sizeof(std::uint64_t),
                                ticks.data(), sizeof(std::uint64_t),
                                VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT),
          "vkGetQueryPoolResults");
    const std::uint32_t bits = context_.physical().timestamp_bits;
    const std::uint64_t mask = bits >= 64 ? ~0ull : ((1ull << bits) - 1);
    const double period_ns = context_.limits().timestampPeriod;
    for (std::size_t i = 0; i < marks_.size(); ++i) {
      const std::uint64_t delta = (ticks[i + 1] - ticks[i]) & mask;
      stages.push_back({marks_[i], double(delta) * period_ns * 1e-6});
    }
  }
  return stages;
}

}  // namespace expanse::detail::vk
