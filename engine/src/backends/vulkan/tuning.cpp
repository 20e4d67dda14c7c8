#include "backends/vulkan/tuning.hpp"

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <string_view>

namespace expanse::detail::vk {
namespace {

const char* variable(const char* name) {
  const char* value = std::getenv(name);
  return value && *value ? value : nullptr;
}

Tuning::Where where(const char* name) {
  const char* value = variable(name);
  if (value && std::string_view(value) == "host") return Tuning::Where::host;
  if (value && std::string_view(value) == "device") return Tuning::Where::device;
  return Tuning::Where::automatic;
}

// A switch: set and not "0".
bool on(const char* name, bool unset) {
  const char* value = variable(name);
  return value ? std::strcmp(value, "0") != 0 : unset;
}

}  // namespace

Tuning tuning_from_environment() {
  Tuning t;
  t.prepare = where("EXPANSE_VULKAN_PREPARE");
  t.bucket = where("EXPANSE_VULKAN_BUCKET");
  t.staged = on("EXPANSE_VULKAN_STAGED", false);
  if (const char* value = variable("EXPANSE_VULKAN_PHASES")) {
    const long k = std::atol(value);
    if (k >= 1 && k <= Tuning::max_phases && (k & (k - 1)) == 0) t.phases = int(k);
  }
  if (const char* value = variable("EXPANSE_VULKAN_CELLS")) {
    if (std::string_view(value) == "uniform") t.cells = Tuning::Cells::uniform;
    if (std::string_view(value) == "quantile") t.cells = Tuning::Cells::quantile;
  }
  t.exact_lattice = on("EXPANSE_VULKAN_EXACT_LATTICE", true);
  t.light_pass = on("EXPANSE_VULKAN_LIGHT_PASS", true);
  if (const char* value = variable("EXPANSE_VULKAN_APEX_FILTERS")) t.apex_filters = std::atoi(value) != 0;
  if (const char* value = variable("EXPANSE_VULKAN_LOOP_BUDGET"))
    t.loop_budget = std::uint32_t(std::clamp(std::atol(value), 1L, long(INT32_MAX)));
  if (const char* value = variable("EXPANSE_VULKAN_KEEP_MB")) t.keep_mb = std::max(0L, std::atol(value));
  if (const char* value = variable("EXPANSE_VULKAN_STAGING_MB")) t.staging_mb = std::max(1L, std::atol(value));
  t.validation = on("EXPANSE_VULKAN_VALIDATION", false);
  return t;
}

bool cpu_device(const Context& ctx) {
  return ctx.physical().properties.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU;
}

std::uint32_t workgroup(const Context& ctx, std::uint32_t wanted) {
  const auto& limits = ctx.limits();
  return std::max(1u, std::min({wanted, limits.maxComputeWorkGroupSize[0], limits.maxComputeWorkGroupInvocations}));
}

// On lavapipe one workgroup = one SIMD batch, so the loop cap (see loop_budget) is shared by as
// few invocations as possible.
std::uint32_t star_workgroup(const Context& ctx) {
  return workgroup(ctx, cpu_device(ctx) ? std::max(1u, ctx.physical().subgroup_size) : 64u);
}

// On a GPU, on the device (prepare_sites.comp, radix_sort.comp): on the H100's host,
// prepare_sites took 117-184 ms at 4096^2 on 16 threads, about as long as the device's whole
// growth (2026-11-25). On a CPU device (lavapipe), on the host: the shaders would run on the
// same cores as prepare_sites' native code.
bool device_prepares(const Context& ctx, const Tuning& tuning) {
  if (tuning.prepare != Tuning::Where::automatic) return tuning.prepare == Tuning::Where::device;
  return !cpu_device(ctx);
}

// On a GPU, on the device (bucket.comp): host-visible memory there is uncached, and the host's
// scattered writes into it were the slowest stage (532 ms at 4096^2 on the H100). On a CPU
// device (lavapipe), on the host: its counting sort writes the buffers in place, and took 17 ms
// at 10^6 where bucket.comp took 200 ms and mapping the ids back 190 ms (2026-11-23).
bool device_buckets(const Context& ctx, const Tuning& tuning) {
  if (tuning.bucket != Tuning::Where::automatic) return tuning.bucket == Tuning::Where::device;
  return !cpu_device(ctx);
}

// In place on a CPU device: pointer chasing on the host costs a load instead of a loop over
// the SIMD lanes.
bool works_in_place(const Context& ctx, const Tuning& tuning) { return cpu_device(ctx) && !tuning.staged; }

// lavapipe breaks out of every loop after 65535 iterations per SIMD batch (8 lanes); a lane
// budget of 1000 keeps the batch under that cap (the shaders also check a canary). In
// star.comp every pass of each of its five loops spends from the budget of a lane taking it,
// so a batch makes at most 5 x 8 x 1000 back-edges; a site needs about 120 (1M uniform), and
// the ~0.07% that would need more are cheaper in the seam stage: 2000 cut the deferrals by a
// quarter but cost more device time than the seam saved. On GPUs a star walk still gets a
// budget, 20,000 units: the kernel lasts as long as its slowest invocation, and the rare walk
// that would scan half the grid is cheaper in the seam stage. Measured on the H100 against
// 65,536 (2026-11-23, two rounds, medians of 5, uniform 256^2 / 512^2 / 1024^2 / 2048^2 /
// 4096^2): star shader 6.2 / 11.2 / 15.3 / 31 / 80 ms against 19 / 37 / 37 / 46 / 108, host to
// host 16 / 29 / 44 / 101-122 / 329-398 against 27-30 / 54-56 / 65 / 121-125 / 336-364.
std::uint32_t loop_budget(const Context& ctx, const Tuning& tuning, bool star) {
  if (tuning.loop_budget != 0) return tuning.loop_budget;
  if (cpu_device(ctx)) return 1000u;
  return star ? 20000u : 1000000000u;
}

// Phases: groups of sites walked one after another, each taking the triangles it shares with
// earlier phases from what their stars posted to its inbox. Four phases of single ids on CPU
// devices: lavapipe, 1M uniform, star shader 755-802 -> 553-560 ms (2026-11-25; two phases
// 586-599, eight 590-604) when a later phase still read the stars that listed themselves; posts
// took it to 529-538 ms against 583-592, kuzmin's unchanged at 1379-1444 (alternated). One phase
// on GPUs: on the H100, two phases with posts (each its own first_pass and edge ring) took
// 4096^2 uniform's star shader from 54.4 to 46.7 ms, but kuzmin's from 106 to 111 and 1024^2
// uniform's from 12.5 to 20.6 (2026-11-25).
int star_phases(const Context& ctx, const Tuning& tuning) {
  if (tuning.phases != 0) return tuning.phases;
  return cpu_device(ctx) ? 4 : 1;
}

// The filters in the edge's frame on CPU devices (lavapipe: star shader -7% at 1M uniform), the
// filters on the points elsewhere (the H100's driver: +6% with the apex filters).
bool apex_filters(const Context& ctx, const Tuning& tuning) {
  if (tuning.apex_filters >= 0) return tuning.apex_filters != 0;
  return cpu_device(ctx);
}

}  // namespace expanse::detail::vk
