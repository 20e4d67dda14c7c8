// The per-site layout on the Vulkan backend: every site walks its own star (shaders/star.comp),
// the adjacency follows from the stars (star_links.comp, or the host in place), step by step.
// Vulkan structs are value-initialised from their sType alone ({VK_STRUCTURE_TYPE_...}).
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#include "backends/vulkan/stars.hpp"

#include <array>
#include <chrono>
#include <cstring>
#include <exception>
#include <optional>
#include <thread>

#include "backends/vulkan/audit.hpp"
#include "backends/vulkan/device_bucketing.hpp"
#include "backends/vulkan/dispatch.hpp"
#include "backends/vulkan/host_bucketing.hpp"
#include "backends/vulkan/host_links.hpp"
#include "backends/vulkan/host_threads.hpp"
#include "backends/vulkan/kept_buffers.hpp"
#include "backends/vulkan/shader_registry.hpp"
#include "backends/vulkan/star_cells.hpp"
#include "expanse/error.hpp"
#include "host_device.h"
#include "predicates/exact_lattice.hpp"
#include "support/timing.hpp"

namespace expanse::detail::vk {
namespace {

using namespace shared;

// Most neighbours a star may have on the device (star.comp's STAR_CAPACITY): longer stars defer.
constexpr std::uint32_t star_capacity = STAR_ROW;
static_assert(star_capacity <= 16, "star info packs star positions and owned masks in 4 and 16 bits");

// One growth of the per-site layout.
class StarGrowth {
 public:
  StarGrowth(Context& ctx, const Tuning& tuning, const GrowInput& input, GrowResult& result, SiteCopy* site_copy)
      : ctx_(ctx),
        tuning_(tuning),
        input_(input),
        result_(result),
        site_copy_(site_copy),
        n_(std::size_t(input.sites.size())),
        per_bucket_(input.layout.sites_per_bucket > 0 ? input.layout.sites_per_bucket : 2.0),
        in_place_(works_in_place(ctx, tuning)),
        device_bucketing_(device_buckets(ctx, tuning)),
        wg_(star_workgroup(ctx)),
        // Each triangle is emitted once and there are at most 2n - 5.
        capacity_(2 * n_),
        // Slots whose adjacency the device cannot find (both far vertices deferred); more than
        // this and the adjacency is left to the host.
        unresolved_capacity_(n_ / 4 + 1024) {}

  void run() {
    plan_grid();
    allocate();
    // Whatever happens below, the cache keeps at most keep_bytes() once this call is over.
    struct Trim {
      Context& ctx;
      ~Trim() {
        try {
          ctx.buffers().trim(ctx.keep_bytes());
        } catch (...) {  // a failed wait: the buffers stay, the call's own error goes on
        }
      }
    } trim{ctx_};
    if (device_bucketing_) bucket_first();
    choose_walks();
    make_kernels();
    Stopwatch watch;
    if (!device_sorted_) {
      if (site_copy_) {  // the host's bucketing reads the sites
        site_copy_->start();
        site_copy_->finish();
      }
      bucket_on_host(ctx_, input_, frame_, *sites_, *cell_start_, *predecessor_, host_grid_);
      result_.host_stages.push_back({"vulkan: bucket", watch.ms()});
      watch.restart();
    }
    // The sites' copy to the host runs beside the stars: submitted after every ring upload
    // (whose barriers would wait for it) and after the bucketing's submission (whose fence
    // would), and the star submission waits for earlier compute work only.
    if (site_copy_) site_copy_->start();
    Recording rec(ctx_);
    record_growth(rec);
    submit(rec, watch);
    read_back();
    link();
  }

 private:
  void plan_grid();
  void allocate();
  void bucket_first();
  void choose_walks();
  void make_kernels();
  void record_growth(Recording& rec);
  void record_phases(Recording& rec);
  void submit(Recording& rec, const Stopwatch& watch);
  void read_back();
  void link();

  Buffer& kept(Kept slot, VkDeviceSize bytes, bool host_visible) { return vk::kept(ctx_, slot, bytes, host_visible); }

  Context& ctx_;
  const Tuning& tuning_;
  const GrowInput& input_;
  GrowResult& result_;
  SiteCopy* site_copy_;  // from prepare_on_device: the sites are on the device, their copy to come
  const std::size_t n_;
  const double per_bucket_;
  const bool in_place_, device_bucketing_;
  const std::uint32_t wg_;
  const std::size_t capacity_, unresolved_capacity_;

  StarCells frame_;
  std::size_t cell_entries_ = 0;
  std::optional<DeviceBucketing> bucketing_;
  // The star kernel's inputs and outputs (host-visible where the host works in place).
  Buffer *sites_ = nullptr, *cell_start_ = nullptr, *predecessor_ = nullptr, *triangles_ = nullptr,
         *counters_ = nullptr, *stars_ = nullptr, *site_info_ = nullptr, *cell_bounds_ = nullptr;
  // The GPU path's: adjacency, unresolved slots, the counters' copy for the host.
  Buffer *neighbors_ = nullptr, *unresolved_ = nullptr, *words_ = nullptr;
  // Device bucketing's inputs in SiteSet order, and the audit's open slots.
  Buffer *input_sites_ = nullptr, *input_predecessor_ = nullptr, *open_slots_ = nullptr;
  // The device audits the adjacency where it has the triangles in SiteSet ids and the hull
  // (device bucketing), and made the adjacency (GPU path).
  bool device_audit_ = false;
  bool device_sorted_ = false;
  StarGrid host_grid_;  // when the host bucketed: its sorted id -> SiteSet id

  int phases_ = 1;
  bool light_ = false, lattice_ = false, edge_apart_ = false;
  // The star kernel's texel views: bound by its descriptor set, so alive until the growth ran.
  std::optional<TexelView> site_view_, cell_view_, predecessor_view_;
  std::vector<Kernel*> first_kernels_;
  Kernel* retry_kernel_ = nullptr;
  Kernel* links_ = nullptr;

  std::uint32_t count_[COUNTER_WORDS]{};
  bool device_links_ = false, check_open_ = false;
  std::vector<std::int32_t> unresolved_slots_, open_list_;
};

void StarGrowth::plan_grid() {
  Stopwatch watch;
  frame_ = plan_star_cells(site_copy_ ? site_copy_->sample() : star_cell_sample(input_.sites), n_,
                           input_.sites.bounds, per_bucket_, ctx_.max_buffer_bytes(), tuning_.cells);
  cell_entries_ = std::size_t(frame_.cells) * std::size_t(frame_.cells) + 1;
  result_.host_stages.push_back({frame_.quantile ? "vulkan: grid (quantile cells)" : "vulkan: grid", watch.ms()});
  ctx_.require_fits(bytes_of(n_, 16), "the sites");
  ctx_.require_fits(bytes_of(cell_entries_, 4), "the grid");
  ctx_.require_fits(bytes_of(capacity_, 12), "the triangle output");
  ctx_.require_fits(bytes_of(n_, 4 * star_capacity), "the stars");
  if (std::max<std::size_t>(n_, cell_entries_) > ctx_.limits().maxTexelBufferElements)
    throw Error(ErrorCode::too_large,
                "Vulkan: " + std::to_string(std::max<std::size_t>(n_, cell_entries_)) +
                    " texels in one texel buffer; device " + ctx_.name() + " allows " +
                    std::to_string(ctx_.limits().maxTexelBufferElements));
}

void StarGrowth::allocate() {
  // Its kernels are compiled on first use only: CPU devices bucket on the host.
  if (device_bucketing_) bucketing_.emplace(ctx_, wg_, frame_.quantile);
  Stopwatch watch;
  const bool in_place = in_place_;
  sites_ = &kept(k_sites, bytes_of(n_, 16), in_place);
  cell_start_ = &kept(k_cell_start, bytes_of(cell_entries_, 4), in_place);
  predecessor_ = &kept(k_predecessor, bytes_of(n_, 4), in_place);
  // Read by the host: in place on a CPU device, else downloaded.
  triangles_ = &kept(k_triangles, bytes_of(capacity_, 12), in_place);
  counters_ = &kept(k_counters, 64, in_place);
  stars_ = &kept(k_stars, bytes_of(n_, 4 * star_capacity), in_place);
  site_info_ = &kept(k_site_info, bytes_of(n_, 8), in_place);
  // Quantile cells' boundaries (a placeholder with uniform cells): written now, before the
  // first submission reads them.
  cell_bounds_ = &kept(k_cell_bounds, std::max<VkDeviceSize>(16, bytes_of(frame_.bounds.size(), 8)), in_place);
  if (!frame_.bounds.empty()) {
    if (in_place) {
      std::memcpy(cell_bounds_->mapped(), frame_.bounds.data(), bytes_of(frame_.bounds.size(), 8));
    } else {
      const StagingRing::Upload bounds[] = {{frame_.bounds.data(), cell_bounds_->handle(), 0, bytes_of(frame_.bounds.size(), 8)}};
      ctx_.staging().upload(bounds);
    }
  }
  // Device bucketing: the inputs in SiteSet order, written by the host (in place on a CPU
  // device, else staged), and buffers the device alone makes and reads.
  if (device_bucketing_) {
    input_sites_ = &kept(k_input_sites, bytes_of(n_, 16), in_place);
    input_predecessor_ = &kept(k_input_predecessor, bytes_of(n_, 4), in_place);
    bucketing_->bind({input_sites_, input_predecessor_, &kept(k_cell_key, bytes_of(n_, 4), false),
                      cell_start_, &kept(k_cursor, bytes_of(cell_entries_ - 1, 4), false),
                      &kept(k_unordered, bytes_of(n_, 4), false), sites_, &kept(k_to_site, bytes_of(n_, 4), false),
                      &kept(k_to_sorted, bytes_of(n_, 4), false), predecessor_, triangles_, counters_,
                      &kept(k_scan_sums, bucketing_->scan_sums_bytes(cell_entries_), false), cell_bounds_});
  }
  device_audit_ = device_bucketing_ && !in_place;
  if (!in_place) {
    neighbors_ = &kept(k_neighbors, bytes_of(capacity_, 12), false);
    unresolved_ = &kept(k_unresolved, bytes_of(unresolved_capacity_, 4), false);
    if (device_audit_) open_slots_ = &kept(k_open_slots, bytes_of(unresolved_capacity_, 4), false);
    // The counters come back here at the end of each submission (the rest by the ring).
    words_ = &kept(k_words, 64, true);
  }
  result_.host_stages.push_back({"vulkan: allocate", watch.ms()});
}

// First submission: the sites into cells. Its one question for the host (was a cell too
// crowded to rank on the device?) is asked before the star kernel runs.
void StarGrowth::bucket_first() {
  Stopwatch watch;
  if (site_copy_) {
    // prepare_on_device left them there.
  } else if (in_place_) {
    copy_on_host_threads(input_sites_->mapped(), input_.sites.points.data(), bytes_of(n_, 16));
    copy_on_host_threads(input_predecessor_->mapped(), input_.hull.predecessor.data(), bytes_of(n_, 4));
  } else {
    // Chunk by chunk through the ring: the host's copy of one chunk overlaps the transfer of
    // the previous one.
    const StagingRing::Upload pieces[] = {
        {input_.sites.points.data(), input_sites_->handle(), 0, bytes_of(n_, 16)},
        {input_.hull.predecessor.data(), input_predecessor_->handle(), 0, bytes_of(n_, 4)}};
    ctx_.staging().upload(pieces);
  }
  if (!site_copy_) result_.host_stages.push_back({"vulkan: stage", watch.ms()});

  watch.restart();
  Recording rec(ctx_);
  rec.barrier();  // after the ring's copies
  GridShape shape{{frame_.origin[0], frame_.origin[1]}, {frame_.inv_width[0], frame_.inv_width[1]}, frame_.cells};
  bucketing_->record_sort(rec, shape, n_);
  rec.timestamp("vulkan: bucket");
  if (!in_place_) rec.copy(*counters_, *words_, counters_->size());
  rec.barrier_to_host();  // the counters (in place: all the host reads)
  for (StageTime& stage : rec.submit()) result_.device_stages.push_back(std::move(stage));
  result_.host_stages.push_back({"vulkan: bucket (submit + wait)", watch.ms()});
  const auto* at = static_cast<const std::uint32_t*>(in_place_ ? counters_->mapped() : words_->mapped());
  device_sorted_ = at[COUNTER_CROWDED_CELL] == 0;
}

// One phase, or the GPU path: a light first_pass (each phase's) and a retry of the sites it
// hands on (star.comp's EXACT_PATH and RETRY); phases in place: every dispatch with the exact
// path. Integer inputs that are no small lattice take the full pass too: the filters leave the
// cocircular cells of nearly every site undecided, and the light pass would hand nearly all of
// them on (a 120 x 120 grid 100 units apart hands on every site).
//
// EXACT_LATTICE, for small integer lattices (exact_lattice.hpp): their ties decided in the
// scan, not the exact loop. The perturbation there is branch-free (cocircular_perturbed_lattice):
// with the loops of the general one, lavapipe's masked lanes ran it for every candidate and its
// 1M lattice star shader went from 1.30 to 2.37 s; now 1.27-1.28 -> 0.65-0.68 s; NVIDIA 4096^2:
// 52.0 -> 23.3 ms (2026-11-25).
//
// One phase or the GPU path, on a device of our own: each phase's sites of the grid's outer ring
// first, then the rest with no barrier between (star.comp's EDGE_PART). Not on a lent device:
// its queue may carry the application's synchronisation validation, which counts two dispatches
// writing one buffer as a hazard even where their sites differ.
void StarGrowth::choose_walks() {
  phases_ = star_phases(ctx_, tuning_);
  const bool one_or_gpu = phases_ == 1 || !in_place_;
  lattice_ = exact_lattice_arithmetic(input_.sites) && tuning_.exact_lattice;
  light_ = one_or_gpu && tuning_.light_pass && (lattice_ || !input_.sites.integer_coordinates);
  edge_apart_ = one_or_gpu && !ctx_.borrowed();
}

void StarGrowth::make_kernels() {
  const VkDescriptorType texel = VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, storage = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
  static const VkDescriptorType star_types[] = {texel, texel, texel, storage, storage, storage, storage, storage};
  site_view_.emplace(ctx_, *sites_, VK_FORMAT_R32G32B32A32_UINT, bytes_of(n_, 16));
  cell_view_.emplace(ctx_, *cell_start_, VK_FORMAT_R32_SINT, bytes_of(cell_entries_, 4));
  predecessor_view_.emplace(ctx_, *predecessor_, VK_FORMAT_R32_SINT, bytes_of(n_, 4));
  Buffer* bindings[] = {sites_, cell_start_, predecessor_, triangles_, counters_, stars_, site_info_, cell_bounds_};
  const TexelView* texels[] = {&*site_view_, &*cell_view_, &*predecessor_view_, nullptr, nullptr, nullptr, nullptr, nullptr};
  // The retry dispatch also decides incircles from exact coordinate differences (star.comp's
  // EXACT_DIFFERENCES).
  auto star_kernel = [&](bool exact_path, bool retry, std::uint32_t edge_part = 0) -> Kernel* {
    std::array<std::uint32_t, STAR_SPEC_COUNT> spec{};
    spec[STAR_SPEC_WORKGROUP] = wg_;
    spec[STAR_SPEC_CAPACITY] = star_capacity;
    spec[STAR_SPEC_LOOP_BUDGET] = loop_budget(ctx_, tuning_, true);
    spec[STAR_SPEC_APEX_FILTERS] = apex_filters(ctx_, tuning_);
    spec[STAR_SPEC_EXACT_LATTICE] = lattice_;
    spec[STAR_SPEC_QUANTILE_CELLS] = frame_.quantile;
    spec[STAR_SPEC_EXACT_PATH] = exact_path;
    spec[STAR_SPEC_RETRY] = retry;
    spec[STAR_SPEC_EXACT_DIFFERENCES] = retry;
    spec[STAR_SPEC_EDGE_PART] = edge_part;
    Kernel& k = ctx_.kernel("star", spirv::star(), 8, sizeof(StarParams), spec, star_types);
    k.bind(bindings, texels);
    return &k;
  };
  if (edge_apart_)
    first_kernels_ = {star_kernel(!light_, false, 1), star_kernel(!light_, false, 2)};
  else
    first_kernels_ = {star_kernel(!light_, false)};
  retry_kernel_ = light_ ? star_kernel(true, true) : nullptr;
  if (!in_place_) {
    std::array<std::uint32_t, LINKS_SPEC_COUNT> link_spec{};
    link_spec[LINKS_SPEC_WORKGROUP] = wg_;
    link_spec[LINKS_SPEC_CAPACITY] = star_capacity;
    links_ = &ctx_.kernel("star_links", spirv::star_links(), 5, sizeof(LinkParams), link_spec);
    Buffer* link_bindings[] = {stars_, site_info_, neighbors_, unresolved_, counters_};
    links_->bind(link_bindings);
  }
}

// The stars, phase by phase (each phase's first_pass kernels), then the retry of the sites the
// light first_pass handed on (a site that was not exits at once).
void StarGrowth::record_phases(Recording& rec) {
  // A scan of more than ~48 sites' worth of cells (at the typical site's density) re-plans on
  // finding a better candidate.
  StarParams params{{frame_.origin[0], frame_.origin[1]}, {frame_.inv_width[0], frame_.inv_width[1]},
                    frame_.cells, int(n_), 0, int(capacity_), int(std::clamp(48.0 / per_bucket_, 4.0, 1.0e6)),
                    0, phases_, 0};
  const std::uint64_t phases = std::uint64_t(phases_);
  for (std::uint64_t phase = 0; phase < phases && phase < n_; ++phase) {
    params.phase = int(phase);
    const std::uint64_t count = (n_ - phase + phases - 1) / phases;
    for (Kernel* kernel : first_kernels_) dispatch_over(ctx_, rec, *kernel, params, params.first_site, count, wg_);
    rec.barrier();
  }
  if (retry_kernel_) {
    params.phase = 0;  // every site, none reading or posting
    params.phase_count = 1;
    dispatch_over(ctx_, rec, *retry_kernel_, params, params.first_site, n_, wg_);
    rec.barrier();
  }
  rec.timestamp("vulkan: stars");
}

void StarGrowth::record_growth(Recording& rec) {
  if (device_sorted_)
    rec.barrier_after_compute();  // no ring copies since the bucketing's submission
  else
    rec.barrier();  // after the ring's copies
  rec.fill(*counters_, 0);
  if (phases_ > 1) rec.fill(*site_info_, ~0u);  // empty inboxes (star.comp)
  rec.barrier();
  record_phases(rec);
  if (links_) {
    LinkParams link_params{int(n_), 0, int(unresolved_capacity_), 0};
    dispatch_over(ctx_, rec, *links_, link_params, link_params.first_site, n_, wg_);
    rec.barrier();
    rec.timestamp("vulkan: links");
  }
  // The triangles are in sorted ids; whoever bucketed maps them back to SiteSet ids.
  if (device_sorted_) {
    bucketing_->record_restore(rec, n_, capacity_);
    rec.timestamp("vulkan: restore ids");
  }
  if (device_sorted_ && device_audit_) {
    record_audit(ctx_, rec, wg_, *triangles_, *neighbors_, *input_predecessor_, *open_slots_, *counters_,
                 capacity_, unresolved_capacity_);
    rec.timestamp("vulkan: audit");
  }
  // Only the counters here: the host reads them, then downloads what was made (not the
  // capacity) through the ring. In place, the host reads the buffers themselves.
  if (!in_place_) rec.copy(*counters_, *words_, counters_->size());
  rec.barrier_to_host();
}

// Submits the growth and waits; while the device works, the host readies the output vectors
// (faulting in 805 MB at 4096^2 took the H100's host ~220 ms in the CUDA backend, overlapped
// with its kernel).
void StarGrowth::submit(Recording& rec, const Stopwatch& watch) {
  std::vector<StageTime> device_stages;
  std::exception_ptr device_failure;
  Clock::time_point device_done;
  std::thread waiter([&] {
    try {
      device_stages = rec.submit();
    } catch (...) {
      device_failure = std::current_exception();
    }
    device_done = Clock::now();
  });
  const auto host_start = Clock::now();
  try {
    // Room for the whole triangulation in both vectors (the seam stage appends in place),
    // sized to it, so the read-back is one parallel copy.
    allocate_full_triangulation(result_.partial, n_, input_.hull.sites.size(), input_.recycled);
  } catch (...) {
    waiter.join();
    throw;
  }
  const auto host_done = Clock::now();
  waiter.join();
  if (device_failure) std::rethrow_exception(device_failure);
  for (StageTime& stage : device_stages) result_.device_stages.push_back(std::move(stage));
  result_.host_stages.push_back({"vulkan: submit + wait", watch.ms()});
  // What the wait above was made of: the device's work (submission to fence, host clock) and
  // the output vectors' allocation beside it; the longer of the two is the wait.
  result_.host_stages.push_back(
      {"vulkan: device work (host clock)", std::chrono::duration<double, std::milli>(device_done - host_start).count()});
  result_.host_stages.push_back({"vulkan: output allocation (host, while the device works)",
                                 std::chrono::duration<double, std::milli>(host_done - host_start).count()});
}

void StarGrowth::read_back() {
  Stopwatch watch;
  auto& partial = result_.partial;
  std::uint32_t* count = count_;
  std::memcpy(count, in_place_ ? counters_->mapped() : words_->mapped(), sizeof(count_));
  if (count[COUNTER_OVERFLOW] != 0 || count[COUNTER_TRIANGLES] > capacity_ ||
      count[COUNTER_TRIANGLES] > partial.triangles.size())
    throw Error(ErrorCode::internal, "Vulkan: star output overflowed its capacity");
  if (count[COUNTER_INVALID_ID] != 0) throw Error(ErrorCode::internal, "Vulkan: the device returned an invalid site id");
  static_assert(sizeof(partial.triangles[0]) == 12 && sizeof(partial.neighbors[0]) == 12);
  const std::size_t made = count[COUNTER_TRIANGLES];
  // The GPU path's adjacency: the links pass hit lavapipe's loop cap, or too many unresolved
  // slots: either way it is left empty (its room kept), and the pipeline derives it.
  device_links_ = !in_place_ && count[COUNTER_LINKS_CUT] == 0 && count[COUNTER_UNRESOLVED_OVERFLOW] == 0;
  check_open_ = device_links_ && device_sorted_ && device_audit_ && count[COUNTER_OPEN_OVERFLOW] == 0;
  if (!in_place_) {
    // Everything the host reads, in one pass through the ring: the triangles (straight into
    // the output vector), the adjacency, and the short lists.
    std::vector<StagingRing::Download> pieces{{triangles_->handle(), 0, partial.triangles.data(), bytes_of(made, 12)}};
    if (device_links_) {
      unresolved_slots_.resize(std::min<std::size_t>(count[COUNTER_UNRESOLVED], unresolved_capacity_));
      pieces.push_back({neighbors_->handle(), 0, partial.neighbors.data(), bytes_of(made, 12)});
      pieces.push_back({unresolved_->handle(), 0, unresolved_slots_.data(), bytes_of(unresolved_slots_.size(), 4)});
    }
    if (check_open_) {
      open_list_.resize(std::min<std::size_t>(count[COUNTER_OPEN_EDGES], unresolved_capacity_));
      pieces.push_back({open_slots_->handle(), 0, open_list_.data(), bytes_of(open_list_.size(), 4)});
    }
    ctx_.staging().download(pieces);
  }
  if (in_place_ && device_sorted_)
    copy_on_host_threads(partial.triangles.data(), triangles_->mapped(), bytes_of(made, 12));
  else if (!device_sorted_)
    // The triangles in sorted ids (downloaded into the output, or in place) to SiteSet ids;
    // each id is read before its slot is written, so the two may be the same memory.
    restore_on_host(host_grid_,
                    static_cast<const std::int32_t*>(in_place_ ? triangles_->mapped()
                                                               : static_cast<void*>(partial.triangles.data())),
                    made, partial);
  partial.triangles.resize(made);
  partial.deferred_expansions = count[COUNTER_DEFERRED];
  result_.iterations = 1;
  result_.host_stages.push_back({"vulkan: read back", watch.ms()});
}

void StarGrowth::link() {
  Stopwatch watch;
  auto& partial = result_.partial;
  if (in_place_) {
    link_stars(static_cast<const std::int32_t*>(stars_->mapped()),
               static_cast<const std::int32_t*>(site_info_->mapped()), n_, partial);
    result_.host_stages.push_back({"vulkan: links (host)", watch.ms()});
    return;
  }
  if (!device_links_) {
    partial.neighbors.clear();
    return;
  }
  partial.neighbors.resize(count_[COUNTER_TRIANGLES]);
  if (unresolved_slots_.size() < count_[COUNTER_UNRESOLVED])
    throw Error(ErrorCode::internal, "Vulkan: more unresolved slots than their capacity");
  pair_unresolved(unresolved_slots_, partial);
  result_.host_stages.push_back({"vulkan: links (read back)", watch.ms()});
  if (!check_open_) return;
  // A failed device audit is final: the pipeline derives the adjacency itself (the host audit
  // would find the same, after reading all of it).
  watch.restart();
  result_.adjacency_audited = count_[COUNTER_BAD_LINKS] == 0 && open_list_.size() == count_[COUNTER_OPEN_EDGES] &&
                              open_edges_check_out(open_list_, unresolved_slots_, partial);
  if (!result_.adjacency_audited) partial.neighbors.clear();
  result_.host_stages.push_back({"vulkan: audit (open edges)", watch.ms()});
}

}  // namespace

void grow_stars(Context& ctx, const Tuning& tuning, const GrowInput& input, GrowResult& result, SiteCopy* site_copy) {
  StarGrowth(ctx, tuning, input, result, site_copy).run();
}

}  // namespace expanse::detail::vk
