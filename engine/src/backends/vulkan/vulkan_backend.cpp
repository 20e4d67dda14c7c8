// The Vulkan Backend: per-site stars (default) and the paper's blocks, on any Vulkan 1.1+
// device with 64-bit floats. Host side only: buffers, dispatch, read-back, one file per pass
// (site_preparation, host_bucketing and device_bucketing, stars, host_links, audit,
// paper_blocks); this file picks the pass and owns the process-wide contexts.
#include "backends/vulkan/vulkan_backend.hpp"

#include <atomic>
#include <cmath>
#include <map>
#include <memory>
#include <mutex>
#include <optional>

#include "backends/backend.hpp"
#include "backends/vulkan/paper_blocks.hpp"
#include "backends/vulkan/site_preparation.hpp"
#include "backends/vulkan/stars.hpp"
#include "backends/vulkan/tuning.hpp"
#include "input/parallel.hpp"
#include "support/timing.hpp"

namespace expanse::detail {
namespace vk {
namespace {

struct Registry {
  std::shared_ptr<Instance> instance;
  std::map<int, std::shared_ptr<Context>> contexts;
  std::mutex mutex;
};
Registry& registry() {
  // Deliberately never destroyed: at exit, drivers (NVIDIA's) may already have torn down their
  // own state, and destroying a device then crashes. The OS reclaims everything anyway.
  static Registry* r = new Registry;
  return *r;
}

std::shared_ptr<Instance> shared_instance_locked(Registry& r) {
  if (!r.instance) r.instance = std::make_shared<Instance>();
  return r.instance;
}

// Device predicates are only valid when no value they form can be subnormal (see
// shaders/include/predicates.glsl): every nonzero |coordinate| must be at least 2^-200.
// A pass over every site, on all host threads (a GPU waits for it).
bool device_safe(const SiteSet& sites) {
  std::atomic<bool> safe{true};
  detail::parallel_chunks(std::size_t(sites.size()), [&](std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
      for (double v : {sites.points[i].x, sites.points[i].y})
        if (v != 0.0 && std::fabs(v) < 0x1p-200) safe.store(false, std::memory_order_relaxed);
  });
  return safe.load();
}

class VulkanBackend final : public Backend {
 public:
  explicit VulkanBackend(std::shared_ptr<Context> context) : context_(std::move(context)) {}
  BackendKind kind() const override { return BackendKind::vulkan; }
  std::string device_name() const override { return context_->name(); }

  GrowResult grow(const GrowInput& input) override {
    std::lock_guard lock(context_->mutex());
    const std::size_t messages = context_->instance().message_count();
    GrowResult result;
    if (!device_safe(input.sites)) {
      // Tiny coordinates could underflow on the device: let the exact CPU stage do it all.
      result.partial.deferred_expansions = std::size_t(input.sites.size());
      return result;
    }
    const Tuning tuning = tuning_from_environment();
    if (input.layout.seeding == Layout::Seeding::paper_blocks)
      grow_blocks(*context_, tuning, input, result);
    else
      grow_stars(*context_, tuning, input, result);
    context_->instance().throw_if_messages(messages);
    return result;
  }

  // Where the per-site layout's sites are prepared (scaled, in Morton order, duplicates
  // merged): device_prepares.
  bool prepares_sites(const Layout& layout) const override {
    if (layout.seeding == Layout::Seeding::paper_blocks) return false;
    return device_prepares(*context_, tuning_from_environment());
  }

  std::optional<InputGrowResult> grow_from_input(const InputGrowInput& input) override {
    if (!prepares_sites(input.layout)) return std::nullopt;
    std::lock_guard lock(context_->mutex());
    const std::size_t messages = context_->instance().message_count();
    std::optional<InputGrowResult> result(std::in_place);
    const Tuning tuning = tuning_from_environment();
    SiteCopy copy(*context_);
    if (!prepare_on_device(*context_, tuning, input, *result, copy)) return std::nullopt;
    const std::size_t m = std::size_t(result->sites.size());
    // Device predicates need every nonzero coordinate at least 2^-200 (device_safe): else the
    // exact CPU stage does it all, as grow() leaves it.
    if (input.scan.smallest_nonzero < 0x1p-200) {
      copy.start();
      copy.finish();
      result->grown.partial.deferred_expansions = m;
    } else {
      grow_stars(*context_, tuning, GrowInput{result->sites, result->hull, input.layout, input.recycled},
                 result->grown, &copy);
    }
    const auto start = Clock::now();
    copy.finish();
    auto& stages = result->grown.host_stages;
    stages.push_back({"vulkan: copy of the sites to the host (while the stars grow)", copy.host_ms});
    stages.push_back({"vulkan: wait for the sites' copy after the growth", ms_since(start)});
    context_->instance().throw_if_messages(messages);
    return result;
  }

 private:
  std::shared_ptr<Context> context_;
};

}  // namespace

std::shared_ptr<Context> shared_context(int index) {
  Registry& r = registry();
  std::lock_guard lock(r.mutex);
  auto found = r.contexts.find(index);
  if (found != r.contexts.end()) return found->second;
  auto context = std::make_shared<Context>(shared_instance_locked(r), index);
  const std::string failure = eft_self_test(*context);
  if (!failure.empty())
    throw Error(ErrorCode::backend_unavailable,
                "Vulkan: device " + context->name() + " fails the exact-arithmetic self-test: " +
                    failure);
  r.contexts[index] = context;
  return context;
}

std::unique_ptr<Backend> make_backend_on(std::shared_ptr<Context> context) {
  return std::make_unique<VulkanBackend>(std::move(context));
}

}  // namespace vk

std::unique_ptr<Backend> make_vulkan_backend(int device) {
  return std::make_unique<vk::VulkanBackend>(vk::shared_context(device));
}

std::vector<DeviceDescription> list_vulkan_devices() {
  auto& r = vk::registry();
  std::shared_ptr<vk::Instance> instance;
  {
    std::lock_guard lock(r.mutex);
    instance = vk::shared_instance_locked(r);
  }
  std::vector<DeviceDescription> devices;
  for (std::size_t i = 0; i < instance->devices().size(); ++i)
    devices.push_back(instance->devices()[i].describe(int(i)));
  return devices;
}

}  // namespace expanse::detail
