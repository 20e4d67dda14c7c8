// expanse::vulkan::Triangulator as a graphics application uses it. The test is the application:
// it makes its own VkInstance (Khronos validation layer on, a debug messenger that fails the run
// on any warning or error) and VkDevice on whatever Vulkan device has 64-bit floats (lavapipe here),
// uploads points into its own device-local buffer, asks Expanse for a Mesh or for its own index
// buffer to be filled, reads that back, and compares with expanse::triangulate on the CPU
// backend and with CGAL. Only the public API is used on the Expanse side.
//
// Exits 77 (ctest: skipped) when there is no Vulkan device with shaderFloat64 or no validation
// layer: never a silent pass.
#define CATCH_CONFIG_RUNNER
#include <catch2/catch.hpp>
#include <dlfcn.h>
#include <vulkan/vulkan.h>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

#include "expanse/check.hpp"
#include "expanse/error.hpp"
#include "expanse/triangulate.hpp"
#include "expanse/vulkan_interop.hpp"
#include "support/cgal_oracle.hpp"
#include "support/test_points.hpp"

// ---- Counting VkDevice and VkInstance creation ------------------------------------------------
// These definitions interpose the loader's exported entry points for this executable (which
// links Expanse statically): every vkCreateDevice/vkCreateInstance, the application's and any
// Expanse might make, is counted and forwarded to the loader. Expanse must make none.
namespace {
std::atomic<int> devices_created{0};
std::atomic<int> instances_created{0};
template <class Fn>
Fn next_symbol(const char* name) {
  void* symbol = dlsym(RTLD_NEXT, name);
  if (symbol == nullptr) throw std::runtime_error(std::string("dlsym(RTLD_NEXT) found no ") + name);
  return reinterpret_cast<Fn>(symbol);
}
}  // namespace

extern "C" VKAPI_ATTR VkResult VKAPI_CALL vkCreateDevice(VkPhysicalDevice physical,
                                                         const VkDeviceCreateInfo* info,
                                                         const VkAllocationCallbacks* allocator,
                                                         VkDevice* device) {
  static const auto next = next_symbol<PFN_vkCreateDevice>("vkCreateDevice");
  ++devices_created;
  return next(physical, info, allocator, device);
}

extern "C" VKAPI_ATTR VkResult VKAPI_CALL vkCreateInstance(const VkInstanceCreateInfo* info,
                                                           const VkAllocationCallbacks* allocator,
                                                           VkInstance* instance) {
  static const auto next = next_symbol<PFN_vkCreateInstance>("vkCreateInstance");
  ++instances_created;
  return next(info, allocator, instance);
}

namespace {

using namespace expanse;

// ---- The application --------------------------------------------------------------------------

std::atomic<int> validation_messages{0};
std::mutex first_message_mutex;
std::string first_message;

VKAPI_ATTR VkBool32 VKAPI_CALL on_message(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                          VkDebugUtilsMessageTypeFlagsEXT,
                                          const VkDebugUtilsMessengerCallbackDataEXT* data,
                                          void*) {
  const char* text = data && data->pMessage ? data->pMessage : "(no text)";
  std::printf("VALIDATION (severity %d): %s\n", int(severity), text);
  if (validation_messages.fetch_add(1) == 0) {
    std::lock_guard lock(first_message_mutex);
    first_message = text;
  }
  return VK_FALSE;
}

void vk_ok(VkResult result, const char* what) {
  if (result != VK_SUCCESS)
    throw std::runtime_error(std::string("test application: ") + what + " failed (" +
                             std::to_string(int(result)) + ")");
}

// A graphics application's own buffer and memory.
struct AppBuffer {
  VkDevice device = VK_NULL_HANDLE;
  VkBuffer buffer = VK_NULL_HANDLE;
  VkDeviceMemory memory = VK_NULL_HANDLE;
  VkDeviceSize size = 0;
  void* mapped = nullptr;
  AppBuffer() = default;
  AppBuffer(const AppBuffer&) = delete;
  AppBuffer& operator=(const AppBuffer&) = delete;
  ~AppBuffer() {
    if (device == VK_NULL_HANDLE) return;
    if (mapped) vkUnmapMemory(device, memory);
    vkDestroyBuffer(device, buffer, nullptr);
    vkFreeMemory(device, memory, nullptr);
  }
};

class App {
 public:
  // Throws std::runtime_error with the reason when this machine cannot host the test.
  App() {
    if (!has_validation_layer())
      throw std::runtime_error("VK_LAYER_KHRONOS_validation is not installed");
    VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
    app.pApplicationName = "expanse interop test (a graphics application)";
    app.apiVersion = VK_API_VERSION_1_2;
    VkDebugUtilsMessengerCreateInfoEXT messenger{
        VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
    // Warnings and errors (INFO is the loader's chatter about manifests and device order).
    messenger.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                                VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
    messenger.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                            VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                            VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
    messenger.pfnUserCallback = &on_message;
    const char* layer = "VK_LAYER_KHRONOS_validation";
    const char* extension = VK_EXT_DEBUG_UTILS_EXTENSION_NAME;
    // Synchronisation validation too: it checks Expanse's barriers against this application's
    // copies (the points are uploaded by a submission Expanse's read must be ordered after).
    const VkValidationFeatureEnableEXT enables[] = {
        VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT};
    VkValidationFeaturesEXT features{VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT};
    features.pNext = &messenger;
    features.enabledValidationFeatureCount = 1;
    features.pEnabledValidationFeatures = enables;
    VkInstanceCreateInfo info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
    info.pNext = &features;
    info.pApplicationInfo = &app;
    info.enabledLayerCount = 1;
    info.ppEnabledLayerNames = &layer;
    info.enabledExtensionCount = 1;
    info.ppEnabledExtensionNames = &extension;
    const VkResult created = vkCreateInstance(&info, nullptr, &instance_);
    if (created != VK_SUCCESS)
      throw std::runtime_error("no Vulkan instance (" + std::to_string(int(created)) + ")");
    auto create_messenger = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance_, "vkCreateDebugUtilsMessengerEXT"));
    vk_ok(create_messenger ? create_messenger(instance_, &messenger, nullptr, &messenger_)
                           : VK_ERROR_EXTENSION_NOT_PRESENT,
          "vkCreateDebugUtilsMessengerEXT");
    pick_device();
    device_ = make_device(true);
    vkGetDeviceQueue(device_, family_, 0, &queue_);
    VkCommandPoolCreateInfo pool{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    pool.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    pool.queueFamilyIndex = family_;
    vk_ok(vkCreateCommandPool(device_, &pool, nullptr, &pool_), "vkCreateCommandPool");
  }

  ~App() {
    triangulator_.reset();
    if (device_) {
      vkDeviceWaitIdle(device_);
      vkDestroyCommandPool(device_, pool_, nullptr);
      vkDestroyDevice(device_, nullptr);
    }
    if (messenger_) {
      auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
          vkGetInstanceProcAddr(instance_, "vkDestroyDebugUtilsMessengerEXT"));
      destroy(instance_, messenger_, nullptr);
    }
    if (instance_) vkDestroyInstance(instance_, nullptr);
  }

  App(const App&) = delete;
  App& operator=(const App&) = delete;

  // The handles the application hands to Expanse, with the features its device was made with.
  vulkan::DeviceHandles handles() const {
    vulkan::DeviceHandles h;
    h.instance = instance_;
    h.physical_device = physical_;
    h.device = device_;
    h.queue = queue_;
    h.queue_family = family_;
    h.enabled_features = enabled_features(true);
    return h;
  }

  // One Triangulator kept for the whole run, as an application would (pipelines compile once).
  vulkan::Triangulator& triangulator() {
    if (!triangulator_) triangulator_ = std::make_unique<vulkan::Triangulator>(handles());
    return *triangulator_;
  }

  std::string device_name() const {
    VkPhysicalDeviceProperties properties;
    vkGetPhysicalDeviceProperties(physical_, &properties);
    return properties.deviceName;
  }

  // A second device of the application's, created *without* shaderFloat64.
  VkDevice make_device_without_fp64() { return make_device(false); }
  static VkPhysicalDeviceFeatures enabled_features(bool fp64) {
    VkPhysicalDeviceFeatures features{};
    features.shaderFloat64 = fp64 ? VK_TRUE : VK_FALSE;
    return features;
  }

  std::unique_ptr<AppBuffer> make_buffer(VkDeviceSize size, VkBufferUsageFlags usage,
                                         bool host_visible) {
    auto b = std::make_unique<AppBuffer>();
    b->device = device_;
    b->size = size;
    VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    info.size = size;
    info.usage = usage;
    info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    vk_ok(vkCreateBuffer(device_, &info, nullptr, &b->buffer), "vkCreateBuffer");
    VkMemoryRequirements requirements;
    vkGetBufferMemoryRequirements(device_, b->buffer, &requirements);
    VkPhysicalDeviceMemoryProperties memory;
    vkGetPhysicalDeviceMemoryProperties(physical_, &memory);
    const VkMemoryPropertyFlags wanted =
        host_visible ? VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT
                     : VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT;
    std::uint32_t type = UINT32_MAX;
    for (std::uint32_t i = 0; i < memory.memoryTypeCount && type == UINT32_MAX; ++i)
      if ((requirements.memoryTypeBits & (1u << i)) &&
          (memory.memoryTypes[i].propertyFlags & wanted) == wanted)
        type = i;
    if (type == UINT32_MAX) throw std::runtime_error("test application: no memory type");
    VkMemoryAllocateInfo allocate{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    allocate.allocationSize = requirements.size;
    allocate.memoryTypeIndex = type;
    vk_ok(vkAllocateMemory(device_, &allocate, nullptr, &b->memory), "vkAllocateMemory");
    vk_ok(vkBindBufferMemory(device_, b->buffer, b->memory, 0), "vkBindBufferMemory");
    if (host_visible)
      vk_ok(vkMapMemory(device_, b->memory, 0, VK_WHOLE_SIZE, 0, &b->mapped), "vkMapMemory");
    return b;
  }

  // The application's vertex data: `points` at byte `offset` of a device-local buffer, uploaded
  // through a staging buffer by a copy it submits to its queue and does NOT wait for: Expanse's
  // contract says work submitted earlier to the same queue is ordered before its read.
  std::unique_ptr<AppBuffer> upload_points(const std::vector<Point2>& points,
                                           VkDeviceSize offset) {
    const VkDeviceSize bytes = std::max<VkDeviceSize>(points.size() * sizeof(Point2), 16);
    auto device_local = make_buffer(offset + bytes,
                                    VK_BUFFER_USAGE_VERTEX_BUFFER_BIT |
                                        VK_BUFFER_USAGE_TRANSFER_SRC_BIT |
                                        VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                    false);
    pending_staging_.push_back(make_buffer(bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, true));
    AppBuffer& staging = *pending_staging_.back();
    std::memcpy(staging.mapped, points.data(), points.size() * sizeof(Point2));
    submit([&](VkCommandBuffer commands) {
      const VkBufferCopy region{0, offset, bytes};
      vkCmdCopyBuffer(commands, staging.buffer, device_local->buffer, 1, &region);
    }, /*wait=*/false);
    return device_local;
  }

  // An index buffer of the application's, every byte set to 0xAB (so untouched bytes show).
  std::unique_ptr<AppBuffer> make_index_buffer(VkDeviceSize size) {
    auto indices = make_buffer(size,
                               VK_BUFFER_USAGE_INDEX_BUFFER_BIT |
                                   VK_BUFFER_USAGE_TRANSFER_DST_BIT |
                                   VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                               false);
    submit([&](VkCommandBuffer commands) {
      vkCmdFillBuffer(commands, indices->buffer, 0, VK_WHOLE_SIZE, 0xABABABABu);
    }, true);
    return indices;
  }

  // Reads a whole buffer back, as the application would to check it.
  std::vector<std::uint32_t> read_back(const AppBuffer& buffer) {
    auto readback = make_buffer(buffer.size, VK_BUFFER_USAGE_TRANSFER_DST_BIT, true);
    submit([&](VkCommandBuffer commands) {
      const VkBufferCopy region{0, 0, buffer.size};
      vkCmdCopyBuffer(commands, buffer.buffer, readback->buffer, 1, &region);
      VkMemoryBarrier barrier{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
      barrier.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
      barrier.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
      vkCmdPipelineBarrier(commands, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT,
                           0, 1, &barrier, 0, nullptr, 0, nullptr);
    }, true);
    std::vector<std::uint32_t> words(buffer.size / 4);
    std::memcpy(words.data(), readback->mapped, words.size() * 4);
    return words;
  }

  // Waits for the application's own outstanding submissions (staging uploads).
  void finish() {
    vk_ok(vkQueueWaitIdle(queue_), "vkQueueWaitIdle");
    for (auto& [commands, fence] : pending_) {
      vkDestroyFence(device_, fence, nullptr);
      vkFreeCommandBuffers(device_, pool_, 1, &commands);
    }
    pending_.clear();
    pending_staging_.clear();
  }

  VkPhysicalDevice physical() const { return physical_; }
  VkDevice device() const { return device_; }
  std::uint32_t family() const { return family_; }

 private:
  static bool has_validation_layer() {
    std::uint32_t count = 0;
    vkEnumerateInstanceLayerProperties(&count, nullptr);
    std::vector<VkLayerProperties> layers(count);
    vkEnumerateInstanceLayerProperties(&count, layers.data());
    for (const auto& l : layers)
      if (std::strcmp(l.layerName, "VK_LAYER_KHRONOS_validation") == 0) return true;
    return false;
  }

  void pick_device() {
    std::uint32_t count = 0;
    vk_ok(vkEnumeratePhysicalDevices(instance_, &count, nullptr), "vkEnumeratePhysicalDevices");
    std::vector<VkPhysicalDevice> devices(count);
    vk_ok(vkEnumeratePhysicalDevices(instance_, &count, devices.data()),
          "vkEnumeratePhysicalDevices");
    for (VkPhysicalDevice d : devices) {
      VkPhysicalDeviceFeatures features;
      vkGetPhysicalDeviceFeatures(d, &features);
      if (!features.shaderFloat64) continue;
      std::uint32_t families = 0;
      vkGetPhysicalDeviceQueueFamilyProperties(d, &families, nullptr);
      std::vector<VkQueueFamilyProperties> props(families);
      vkGetPhysicalDeviceQueueFamilyProperties(d, &families, props.data());
      // A graphics application's queue: graphics and compute in one family.
      for (std::uint32_t f = 0; f < families; ++f)
        if ((props[f].queueFlags & VK_QUEUE_GRAPHICS_BIT) &&
            (props[f].queueFlags & VK_QUEUE_COMPUTE_BIT)) {
          physical_ = d;
          family_ = f;
          return;
        }
    }
    throw std::runtime_error("no Vulkan device with shaderFloat64 and a graphics+compute queue (" +
                             std::to_string(count) + " device(s))");
  }

  VkDevice make_device(bool fp64) {
    const float priority = 1.0f;
    VkDeviceQueueCreateInfo queue{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    queue.queueFamilyIndex = family_;
    queue.queueCount = 1;
    queue.pQueuePriorities = &priority;
    const VkPhysicalDeviceFeatures features = enabled_features(fp64);
    VkDeviceCreateInfo info{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
    info.queueCreateInfoCount = 1;
    info.pQueueCreateInfos = &queue;
    info.pEnabledFeatures = &features;
    VkDevice device = VK_NULL_HANDLE;
    vk_ok(vkCreateDevice(physical_, &info, nullptr, &device), "vkCreateDevice");
    return device;
  }

  template <class Record>
  void submit(Record&& record, bool wait) {
    VkCommandBufferAllocateInfo allocate{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    allocate.commandPool = pool_;
    allocate.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    allocate.commandBufferCount = 1;
    VkCommandBuffer commands;
    vk_ok(vkAllocateCommandBuffers(device_, &allocate, &commands), "vkAllocateCommandBuffers");
    VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    vk_ok(vkBeginCommandBuffer(commands, &begin), "vkBeginCommandBuffer");
    record(commands);
    vk_ok(vkEndCommandBuffer(commands), "vkEndCommandBuffer");
    VkFenceCreateInfo fence_info{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    VkFence fence;
    vk_ok(vkCreateFence(device_, &fence_info, nullptr, &fence), "vkCreateFence");
    VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    submit.commandBufferCount = 1;
    submit.pCommandBuffers = &commands;
    vk_ok(vkQueueSubmit(queue_, 1, &submit, fence), "vkQueueSubmit");
    pending_.emplace_back(commands, fence);
    if (wait) finish();
  }

  VkInstance instance_ = VK_NULL_HANDLE;
  VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
  VkPhysicalDevice physical_ = VK_NULL_HANDLE;
  std::uint32_t family_ = 0;
  VkDevice device_ = VK_NULL_HANDLE;
  VkQueue queue_ = VK_NULL_HANDLE;
  VkCommandPool pool_ = VK_NULL_HANDLE;
  std::vector<std::pair<VkCommandBuffer, VkFence>> pending_;
  std::vector<std::unique_ptr<AppBuffer>> pending_staging_;
  std::unique_ptr<vulkan::Triangulator> triangulator_;
};

std::unique_ptr<App> the_app;
int app_devices = 0;  // vkCreateDevice calls the application made itself

App& app() { return *the_app; }

// Every test ends here: no validation message, no VkInstance or VkDevice made by Expanse.
void expect_clean() {
  app().finish();
  const int messages = validation_messages.load();
  INFO("first validation message: " << first_message);
  CHECK(messages == 0);
  CHECK(devices_created.load() == app_devices);
  CHECK(instances_created.load() == 1);
}

// ---- Helpers ----------------------------------------------------------------------------------

constexpr std::uint32_t untouched = 0xABABABABu;

std::vector<Triangle> as_triangles(const std::vector<std::uint32_t>& words, VkDeviceSize offset,
                                   std::size_t count) {
  std::vector<Triangle> t(count);
  for (std::size_t i = 0; i < count; ++i)
    for (std::size_t k = 0; k < 3; ++k)
      t[i][k] = std::int32_t(words[std::size_t(offset / 4) + 3 * i + k]);
  return t;
}

bool all_untouched(const std::vector<std::uint32_t>& words, std::size_t from = 0,
                   std::size_t to = std::numeric_limits<std::size_t>::max()) {
  for (std::size_t i = from; i < std::min(to, words.size()); ++i)
    if (words[i] != untouched) return false;
  return true;
}

Mesh reference(const std::vector<Point2>& points) {
  Options cpu;
  cpu.backend = BackendKind::cpu;
  return triangulate(points, cpu);
}

struct Case {
  const char* name;
  std::vector<Point2> points;
};

std::vector<Case> cases() {
  std::vector<Case> c;
  c.push_back({"uniform 3000", test::points::uniform(3000, 1)});
  c.push_back({"grid 1600 (cocircular)", test::points::grid(1600, 2)});
  c.push_back({"grid with duplicates 1200", test::points::grid_with_duplicates(1200, 3)});
  c.push_back({"duplicates 1500", test::points::duplicates(1500, 4)});
  c.push_back({"square boundary 400 (all hull, collinear hull sites)",
               test::points::square_boundary(400, 5)});
  // Collinear hull sites around a random interior, every side point repeated once.
  Case hull{"collinear hull + interior + duplicates", {}};
  test::TestRandom random(6);
  for (int k = 0; k <= 20; ++k)
    for (int copy = 0; copy < 2; ++copy) {
      hull.points.push_back({double(k), 0});
      hull.points.push_back({double(k), 20});
      hull.points.push_back({0, double(k)});
      hull.points.push_back({20, double(k)});
    }
  for (int k = 0; k < 300; ++k)
    hull.points.push_back({1 + 18 * random.uniform(), 1 + 18 * random.uniform()});
  test::shuffle(hull.points, random);
  c.push_back(hull);
  c.push_back({"collinear plus one 300", test::points::collinear_plus_one(300, 7)});
  return c;
}

// ---- Tests ------------------------------------------------------------------------------------

TEST_CASE("index buffer: the same triangles as expanse::triangulate and CGAL") {
  vulkan::Triangulator& triangulator = app().triangulator();
  for (const Case& c : cases()) {
    INFO(c.name);
    const VkDeviceSize offset = 48;           // the points do not start the buffer
    const VkDeviceSize indices_offset = 24;   // nor do the indices
    auto points = app().upload_points(c.points, offset);
    const VkDeviceSize capacity = vulkan::max_index_buffer_bytes(c.points.size());
    auto indices = app().make_index_buffer(indices_offset + capacity + 32);
    const vulkan::IndexBufferResult written = triangulator.triangulate_to_index_buffer(
        points->buffer, offset, c.points.size(), indices->buffer, indices_offset, capacity);
    const Mesh expected = reference(c.points);
    REQUIRE(written.triangles == expected.triangles.size());
    CHECK(written.bytes_written == 12 * written.triangles);
    CHECK(written.stats.device == app().device_name());
    CHECK(written.stats.backend == "vulkan");
    const std::vector<std::uint32_t> words = app().read_back(*indices);
    const std::vector<Triangle> triangles = as_triangles(words, indices_offset, written.triangles);
    const test::Comparison same = test::compare_triangles(triangles, expected.triangles);
    INFO(same.message);
    CHECK(same.equal);
    const test::Comparison cgal =
        test::compare_triangles(triangles, test::cgal_delaunay(c.points).triangles);
    INFO(cgal.message);
    CHECK(cgal.equal);
    // Nothing before indices_offset or after the triangles was written.
    CHECK(all_untouched(words, 0, indices_offset / 4));
    CHECK(all_untouched(words, indices_offset / 4 + 3 * written.triangles));
    std::printf("  %-52s %6zu triangles (gpu %zu, seam %zu)\n", c.name, written.triangles,
                written.stats.gpu_triangles, written.stats.seam_triangles);
  }
  expect_clean();
}

TEST_CASE("Mesh: the same mesh as expanse::triangulate, checked, made on the app's device") {
  vulkan::Triangulator& triangulator = app().triangulator();
  for (const Case& c : cases()) {
    INFO(c.name);
    auto points = app().upload_points(c.points, 0);
    const Mesh mesh = triangulator.triangulate(points->buffer, 0, c.points.size());
    const Mesh expected = reference(c.points);
    const test::Comparison same = test::compare_triangles(mesh.triangles, expected.triangles);
    INFO(same.message);
    CHECK(same.equal);
    CHECK(mesh.hull == expected.hull);
    CHECK(mesh.representative == expected.representative);
    CHECK(mesh.neighbors.size() == mesh.triangles.size());
    const CheckReport report = check_mesh(c.points, mesh);
    INFO((report.problems.empty() ? std::string() : report.problems.front()));
    CHECK(report.ok);
    CHECK(mesh.stats.device == app().device_name());
  }
  // The front growth really ran on the application's device.
  const std::vector<Point2> uniform = test::points::uniform(3000, 11);
  auto points = app().upload_points(uniform, 0);
  const Mesh mesh = triangulator.triangulate(points->buffer, 0, uniform.size());
  CHECK(mesh.stats.gpu_triangles * 10 >= mesh.triangles.size() * 9);
  expect_clean();
}

TEST_CASE("index buffer: too small a capacity throws too_large and writes nothing") {
  vulkan::Triangulator& triangulator = app().triangulator();
  const std::vector<Point2> pts = test::points::uniform(500, 21);
  const std::size_t needed = 12 * reference(pts).triangles.size();
  auto points = app().upload_points(pts, 0);
  auto indices = app().make_index_buffer(vulkan::max_index_buffer_bytes(pts.size()));
  try {
    triangulator.triangulate_to_index_buffer(points->buffer, 0, pts.size(), indices->buffer, 0,
                                             needed - 12);
    FAIL("no exception");
  } catch (const Error& e) {
    CHECK(e.code() == ErrorCode::too_large);
    INFO(e.what());
    CHECK(std::string(e.what()).find(std::to_string(needed) + " bytes") != std::string::npos);
  }
  CHECK(all_untouched(app().read_back(*indices)));
  // Exactly the bytes needed is enough.
  const auto written = triangulator.triangulate_to_index_buffer(points->buffer, 0, pts.size(),
                                                                indices->buffer, 0, needed);
  CHECK(written.bytes_written == needed);
  const auto words = app().read_back(*indices);
  CHECK(all_untouched(words, needed / 4));
  CHECK(!all_untouched(words, 0, needed / 4));
  expect_clean();
}

TEST_CASE("index buffer: NaN or Inf points throw invalid_input and write nothing") {
  vulkan::Triangulator& triangulator = app().triangulator();
  for (double bad : {std::numeric_limits<double>::quiet_NaN(),
                     std::numeric_limits<double>::infinity()}) {
    std::vector<Point2> pts = test::points::uniform(200, 31);
    pts[137].y = bad;
    auto points = app().upload_points(pts, 0);
    auto indices = app().make_index_buffer(vulkan::max_index_buffer_bytes(pts.size()));
    try {
      triangulator.triangulate_to_index_buffer(points->buffer, 0, pts.size(), indices->buffer, 0,
                                               vulkan::max_index_buffer_bytes(pts.size()));
      FAIL("no exception");
    } catch (const Error& e) {
      CHECK(e.code() == ErrorCode::invalid_input);
      INFO(e.what());
      CHECK(std::string(e.what()).find("137") != std::string::npos);  // names the point
    }
    CHECK(all_untouched(app().read_back(*indices)));
    CHECK_THROWS_AS(triangulator.triangulate(points->buffer, 0, pts.size()), Error);
  }
  expect_clean();
}

TEST_CASE("index buffer: 0, 1, 2 points and all-collinear points give no triangles") {
  vulkan::Triangulator& triangulator = app().triangulator();
  CHECK(vulkan::max_triangles(0) == 0);
  CHECK(vulkan::max_triangles(2) == 0);
  CHECK(vulkan::max_triangles(3) == 1);
  CHECK(vulkan::max_index_buffer_bytes(10) == 12 * 15);
  auto indices = app().make_index_buffer(64);
  // count 0: nothing is read, the points buffer may be null.
  auto none = triangulator.triangulate_to_index_buffer(VK_NULL_HANDLE, 0, 0, indices->buffer, 0, 0);
  CHECK(none.triangles == 0);
  CHECK(triangulator.triangulate(VK_NULL_HANDLE, 0, 0).triangles.empty());
  const std::vector<std::vector<Point2>> small = {
      {{1, 2}}, {{1, 2}, {3, 4}}, {{1, 2}, {1, 2}, {1, 2}}, {{0, 0}, {1, 1}, {2, 2}, {3, 3}}};
  for (const auto& pts : small) {
    auto points = app().upload_points(pts, 0);
    const auto written = triangulator.triangulate_to_index_buffer(
        points->buffer, 0, pts.size(), indices->buffer, 0, 0);
    CHECK(written.triangles == 0);
    CHECK(written.bytes_written == 0);
    const Mesh mesh = triangulator.triangulate(points->buffer, 0, pts.size());
    CHECK(mesh.triangles.empty());
    CHECK(mesh.hull == reference(pts).hull);
  }
  CHECK(all_untouched(app().read_back(*indices)));
  expect_clean();
}

TEST_CASE("constructor: clear errors for a device Expanse cannot use") {
  // A device of the application's created without shaderFloat64 (lavapipe supports it, so this
  // is the way to get an fp64-less device here; a device without support fails the same check
  // one step earlier, with its own message).
  VkDevice no_fp64 = app().make_device_without_fp64();
  ++app_devices;
  vulkan::DeviceHandles h = app().handles();
  h.device = no_fp64;
  vkGetDeviceQueue(no_fp64, app().family(), 0, &h.queue);
  h.enabled_features = App::enabled_features(false);
  try {
    vulkan::Triangulator t(h);
    FAIL("no exception");
  } catch (const Error& e) {
    CHECK(e.code() == ErrorCode::backend_unavailable);
    INFO(e.what());
    CHECK(std::string(e.what()).find("shaderFloat64") != std::string::npos);
  }
  vkDestroyDevice(no_fp64, nullptr);

  h = app().handles();
  h.queue_family = 99;
  CHECK_THROWS_MATCHES(vulkan::Triangulator(h), Error,
                       Catch::Predicate<Error>([](const Error& e) {
                         return e.code() == ErrorCode::invalid_argument;
                       }));
  h = app().handles();
  h.device = VK_NULL_HANDLE;
  CHECK_THROWS_MATCHES(vulkan::Triangulator(h), Error,
                       Catch::Predicate<Error>([](const Error& e) {
                         return e.code() == ErrorCode::invalid_argument;
                       }));
  expect_clean();
}

TEST_CASE("Triangulator: moved, destroyed and made again on the same device") {
  std::vector<Point2> pts = test::points::uniform(400, 41);
  auto points = app().upload_points(pts, 0);
  const Mesh expected = reference(pts);
  {
    vulkan::Triangulator first(app().handles());
    vulkan::Triangulator moved(std::move(first));
    CHECK(test::compare_triangles(moved.triangulate(points->buffer, 0, pts.size()).triangles,
                                  expected.triangles)
              .equal);
  }  // destroys only Expanse's objects: the application's device keeps working
  vulkan::Triangulator again(app().handles());
  CHECK(test::compare_triangles(again.triangulate(points->buffer, 0, pts.size()).triangles,
                                expected.triangles)
            .equal);
  expect_clean();
}

}  // namespace

int main(int argc, char** argv) {
  try {
    the_app = std::make_unique<App>();
    app_devices = devices_created.load();
    if (app_devices != 1 || instances_created.load() != 1) {
      std::printf("FAILED: counting vkCreateDevice/vkCreateInstance does not work (%d, %d)\n",
                  app_devices, instances_created.load());
      return 1;
    }
    std::printf("vulkan interop tests on %s (the application's own device)\n",
                app().device_name().c_str());
  } catch (const std::exception& e) {
    std::printf("SKIPPED: %s\n", e.what());
    return 77;
  }
  int failed = Catch::Session().run(argc, argv);
  the_app.reset();  // the application tears down; the layer watches that too
  if (validation_messages.load() != 0) {
    std::printf("FAILED: %d validation message(s); first: %s\n", validation_messages.load(),
                first_message.c_str());
    failed = failed ? failed : 1;
  }
  return failed;
}
