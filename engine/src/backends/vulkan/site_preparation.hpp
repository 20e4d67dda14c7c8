#pragma once
// The per-site layout's input prepared on the device (device_preparation.hpp), and the copy of
// the prepared sites to the host beside the growth.
#include <future>
#include <optional>
#include <vector>

#include "backends/backend.hpp"
#include "backends/vulkan/star_cells.hpp"
#include "backends/vulkan/tuning.hpp"
#include "backends/vulkan/vk_context.hpp"

namespace expanse::detail::vk {

// The prepared sites, their input indices and (where points repeat) the representatives,
// copied to the host while the stars grow: one submission of copies into a kept host-visible
// buffer, untimed (the timed star submission owns the query pool), then the host's copy out
// of it on another thread. On the H100 the copy through the ring before the growth took
// 24-26 ms of 229-261 at 4096^2 (2026-11-25).
struct SiteCopy {
  struct Piece {
    Buffer* from;
    void* to;
    VkDeviceSize bytes;
  };
  explicit SiteCopy(Context& context) : ctx(context) {}
  ~SiteCopy() {
    if (host.valid()) host.wait();
  }
  SiteCopy(const SiteCopy&) = delete;
  SiteCopy& operator=(const SiteCopy&) = delete;

  /// Submits the copies into `staging` and starts the host's copy out of it.
  void start();
  // Waits for the host's copy (on the thread that holds the context) and frees the recording.
  void finish() {
    if (host.valid()) host.get();
    rec.reset();
  }

  // What stands in for the sites on the host until the copy has run: star_cell_sample's
  // sample of them, every star_cell_sample_stride(n)-th site.
  SiteSample sample() const { return {sample_points.data(), 1, sample_points.size()}; }

  Context& ctx;
  std::vector<Point2> sample_points;
  Buffer* staging = nullptr;
  std::vector<Piece> pieces;
  std::optional<Recording> rec;
  std::future<void> host;
  double host_ms = 0.0;
};

/// The raw input prepared on the device, as prepare_sites and convex_hull would have made it
/// for the rest of the pipeline: the sites and their input indices, the representatives and
/// the hull come back to the host (the seam stage and the output need them; `copy` brings the
/// sites beside the growth); the sites and the hull predecessors stay in k_input_sites and
/// k_input_predecessor for grow_stars. False, with nothing consumed, when the device cannot
/// (too large for its buffers) or the hull is degenerate: the host prepares instead.
bool prepare_on_device(Context& ctx, const Tuning& tuning, const InputGrowInput& input,
                       InputGrowResult& result, SiteCopy& copy);

}  // namespace expanse::detail::vk
