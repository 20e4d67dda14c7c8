#pragma once
// The Vulkan backend's knobs: defaults and limits here, read from the environment by
// tuning_from_environment() (the backend's only getenv), documented in docs/tuning.md.
// A knob changes speed or memory, never the triangulation.
#include <cstdint>

#include "backends/vulkan/vk_context.hpp"

namespace expanse::detail::vk {

struct Tuning {
  /// Where a pass runs: chosen by the device (GPU: device, CPU device: host), or forced.
  enum class Where { automatic, host, device };
  /// Which cells the star grid uses: chosen from a sample of the sites, or forced.
  enum class Cells { automatic, uniform, quantile };

  /// EXPANSE_VULKAN_PREPARE=host|device: where the per-site layout's sites are prepared
  /// (scaled, Morton-sorted, duplicates merged). The tests force `device` on lavapipe.
  Where prepare = Where::automatic;
  /// EXPANSE_VULKAN_BUCKET=host|device: where the sites are sorted into cells. The tests run
  /// both on lavapipe.
  Where bucket = Where::automatic;
  /// EXPANSE_VULKAN_STAGED=1: the GPU path on any device (staging copies, star_links.comp)
  /// instead of a CPU device's in-place buffers; the tests use it to run that path on lavapipe.
  bool staged = false;
  /// EXPANSE_VULKAN_PHASES=1|2|4|8|16: phases of the star walk; 0 picks (4 on CPU devices, 1
  /// on GPUs). The conformance runs force 2 and 8 on lavapipe to cover the GPU path's phases.
  int phases = 0;
  static constexpr int max_phases = 16;
  /// EXPANSE_VULKAN_CELLS=uniform|quantile: the star grid's cells.
  Cells cells = Cells::automatic;
  /// EXPANSE_VULKAN_EXACT_LATTICE=0: small integer lattices through the exact loop like any
  /// input instead of star.comp's EXACT_LATTICE scan (a conformance run covers that loop).
  bool exact_lattice = true;
  /// EXPANSE_VULKAN_LIGHT_PASS=0: one phase walked in one full pass with the exact path instead
  /// of the light first_pass and its retry (a test compares the two).
  bool light_pass = true;
  /// EXPANSE_VULKAN_APEX_FILTERS=0|1: star.comp's candidate filters in the edge's frame (1) or
  /// on the points (0); -1 picks (1 on CPU devices, 0 on GPUs). A test forces 0 on lavapipe.
  int apex_filters = -1;
  /// EXPANSE_VULKAN_LOOP_BUDGET: loop iterations a star walk may spend before its site defers
  /// to the seam stage; 0 picks (1000 on CPU devices, 20000 on GPUs; blocks: 1000 on CPU
  /// devices, unbounded on GPUs). At least 1.
  std::uint32_t loop_budget = 0;
  /// EXPANSE_VULKAN_KEEP_MB: device memory the context keeps cached between calls, in MiB;
  /// -1 picks a quarter of the largest device-local heap, 0 releases after every call.
  std::int64_t keep_mb = -1;
  /// EXPANSE_VULKAN_STAGING_MB: size of each of the staging ring's two host-visible slots, MiB
  /// (at least 1).
  std::int64_t staging_mb = 32;
  /// EXPANSE_VULKAN_VALIDATION=1: the Khronos validation layer, any message an error (tests).
  bool validation = false;
};

/// The knobs as the environment sets them now (read on every call: tests change them between
/// calls); unset or unparsable variables keep the defaults.
Tuning tuning_from_environment();

// ---- The automatic choices, resolved for a device --------------------------------------------

/// A CPU device (lavapipe): its shaders run on the host's cores.
bool cpu_device(const Context& ctx);

/// `wanted` invocations a workgroup, within the device's limits.
std::uint32_t workgroup(const Context& ctx, std::uint32_t wanted);

/// Invocations a workgroup of the per-site kernels.
std::uint32_t star_workgroup(const Context& ctx);

/// Where the per-site layout's sites are prepared: true on the device.
bool device_prepares(const Context& ctx, const Tuning& tuning);

/// Where the star grid's sites are sorted into cells: true on the device.
bool device_buckets(const Context& ctx, const Tuning& tuning);

/// A CPU device's buffers are written and read in place, with no staging copies, and the
/// adjacency is derived from the stars on the host; false: the GPU path.
bool works_in_place(const Context& ctx, const Tuning& tuning);

/// Loop iterations a walk may spend (star.comp's and blocks.comp's LOOP_BUDGET).
std::uint32_t loop_budget(const Context& ctx, const Tuning& tuning, bool star);

/// Phases of the star walk (a power of two).
int star_phases(const Context& ctx, const Tuning& tuning);

/// star.comp's APEX_FILTERS.
bool apex_filters(const Context& ctx, const Tuning& tuning);

}  // namespace expanse::detail::vk
