// Per-site star layout: every site grows its own star independently (docs/algorithm.md).
//
//   upload -> bucket (cell keys, radix sort, gather, cell starts, hull predecessors)
//          -> stars (nearest_site, CCW walk, CW walk; count owned triangles)
//          -> scan (triangle offsets)  [one 8-byte read-back: output size + deferred count]
//          -> emit (triangles in site ids + neighbours from the stars) -> audit -> download
//
// Work runs in sorted-by-cell order ("local ids"): neighbouring threads walk neighbouring
// cells, so their point reads share cache lines. A triangle is owned by its smallest local id;
// any total order works, each triangle is still emitted exactly once.
#include <cub/device/device_radix_sort.cuh>
#include <cub/device/device_scan.cuh>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <functional>
#include <future>
#include <memory>
#include <optional>
#include <type_traits>

#include "bucket_kernels.cuh"
#include "cuda_internal.hpp"
#include "grid_copies.cuh"
#include "input/parallel.hpp"
#include "star_emit.cuh"
#include "star_grid.hpp"
#include "star_walk_kernels.cuh"
#include "support/timing.hpp"

namespace expanse::detail::cuda {
namespace {

constexpr int kThreads = 256;

/// f(std::integral_constant<int, 4, 6 or 8>): the kernels are compiled for these three.
template <class F>
void with_star_blocks(int blocks, F&& f) {
  if (blocks >= 8)
    f(std::integral_constant<int, 8>{});
  else if (blocks <= 4)
    f(std::integral_constant<int, 4>{});
  else
    f(std::integral_constant<int, 6>{});
}
/// Device memory per site of the star layout: points twice, cell keys and ids twice, rank,
/// predecessor, owned, offset, retry, handed on; the star row; triangles and neighbours (about 2
/// a site); an inbox (StarInbox) for every other site.
std::size_t per_site_bytes() {
  return 2 * sizeof(double2) + 2 * 2 * sizeof(std::uint32_t) + 9 * sizeof(int) + kStar * sizeof(int) +
         2 * 2 * 3 * sizeof(int) + sizeof(int) + (kInboxWords + 1) * sizeof(int) / 2 + 64;
}
int blocks_for(std::size_t n, int threads = kThreads) { return static_cast<int>((n + threads - 1) / threads); }

/// How one input's stars are walked, decided on the host before the walks (docs/tuning.md gives
/// the measurement behind each default).
struct WalkPlan {
  unsigned budget = 0;        ///< a site's whole walk (and the edge's retry)
  unsigned pass_budget = 0;   ///< the first pass's, or the only pass's
  unsigned retry_budget = 0;  ///< the interior sites' retry
  bool two_passes = false;    ///< a first pass, then the retry by warps
  /// The first pass walks light (walk_star_boxes' FirstPass) unless the input is integer but no
  /// small lattice: there the filters leave the cocircular cells of nearly every site undecided,
  /// and a light pass would hand nearly all of them on to the retry, a warp a site (a 120 x 120
  /// grid 100 units apart hands on every site).
  bool light = false;
  WalkPass pass = WalkPass::only;
  int phases = 1;
  /// The phases' blocks start from both ends of the cell order (ends_first_block), on quantile
  /// cells: their first and last rows hold the far tails in y, whose sites walk longest.
  bool ends_first = false;
  /// The first phase's retries run on the edge's stream beside the second phase
  /// (launch_first_phase_retry).
  bool early_retry = false;
  /// The edge's retry on ctx.low_stream (edge_retry_blocks a launch) rather than the edge's stream.
  bool edge_retry_low = false;
  int retry_blocks = 0, edge_retry_blocks = 0;
  StarBlocks blocks;
  EdgeCells edge;  ///< the sites the edge's stream walks (none: keys null)
};

/// The sites' arrays of the walks that live only through them: the edge's lists, the inboxes.
struct WalkArrays {
  WalkArrays(std::size_t n, const WalkPlan& plan, cudaStream_t stream)
      : edge(plan.edge.keys ? 3 * n : 0, stream),
        inbox_slots((plan.phases == 2 ? n / 2 + 1 : 0) * kInboxWords, stream),
        inbox_counts(plan.phases == 2 ? n / 2 + 1 : 0, stream) {
    if (inbox_counts.bytes() > 0) EXPANSE_CUDA(cudaMemsetAsync(inbox_counts.get(), 0, inbox_counts.bytes(), stream));
  }
  /// The edge's site list, its retry list and its handed-on list, n words each.
  DeviceArray<int> edge;
  DeviceArray<int> inbox_slots;
  DeviceArray<std::uint32_t> inbox_counts;
  int* edge_sites() { return edge.get(); }
  int* edge_retry(std::size_t n) { return edge.bytes() ? edge.get() + n : nullptr; }
  int* edge_handed_on(std::size_t n) { return edge.bytes() ? edge.get() + 2 * n : nullptr; }
};

/// Events of one walk of the stars across the streams; destroyed with it.
struct WalkEvents {
  cudaEvent_t fork = nullptr, join = nullptr, stripped = nullptr, phase0_done = nullptr;
  cudaEvent_t edge_passed = nullptr;  ///< set where the edge's retry went to ctx.low_stream
  static cudaEvent_t make() {
    cudaEvent_t e = nullptr;
    EXPANSE_CUDA(cudaEventCreateWithFlags(&e, cudaEventDisableTiming));
    return e;
  }
  WalkEvents() = default;
  WalkEvents(const WalkEvents&) = delete;
  WalkEvents& operator=(const WalkEvents&) = delete;
  ~WalkEvents() {
    for (cudaEvent_t e : {fork, join, stripped, phase0_done, edge_passed})
      if (e) cudaEventDestroy(e);
  }
};

/// The output's read-back words (ctx.pinned_words): [0] triangles, [1..7] counter words 0..6:
/// [1] deferred, [3..4] predicates (u64), [5] max work per site, [6] sites over 4096 work units,
/// [7] sites deferred by the work budget.
struct StarSizes {
  unsigned int words[8];
};

/// One triangulation by the star layout, step by step (grow_per_site runs them in order). The
/// device arrays are members in the order they are allocated from the stream's pool.
class StarRun {
 public:
  StarRun(Context& ctx, const GrowInput& input, GrowResult& result, const SitesOnDevice* on_device,
          const Tuning& tuning);
  void upload();
  void bucket();
  WalkPlan plan_walks() const;
  void walk_stars(const WalkPlan& plan);
  void scan();
  std::size_t emit();
  void pin_output();
  StarSizes read_sizes();
  void audit(std::size_t triangle_count);
  void download(std::size_t triangle_count);
  void report(const StarSizes& sizes);

 private:
  template <int FirstB, int LaterB, int EdgeB, bool Exact, bool Striped>
  void walk_passes(const WalkPlan& plan, WalkArrays& arrays);
  template <int EdgeB, bool Exact, bool Striped>
  void launch_edge(const WalkPlan& plan, WalkArrays& arrays, WalkEvents& events);
  template <int FirstB, bool Exact, bool Striped>
  void launch_first_phase_retry(const WalkPlan& plan, WalkEvents& events);
  template <class First, class LaterList>
  void walk_phases(const WalkPlan& plan, WalkArrays& arrays, First first, LaterList later_list, int* handed_on,
                   const std::function<void()>& after_phase0);
  void link_open_pairs(std::size_t triangle_count, unsigned open, std::size_t room, std::uint64_t* keys,
                       int* slots, std::uint64_t* keys_sorted, int* slots_sorted);
  void run_audit_kernel(std::size_t triangle_count, std::uint64_t* open_keys, int* open_slots, std::size_t room);

  Context& ctx_;
  const GrowInput& input_;
  GrowResult& result_;
  const SitesOnDevice* on_device_;
  const Tuning tuning_;
  const cudaStream_t stream_;
  const std::size_t n_;
  const GridShape shape_;
  StageTimer timer_;
  StreamTimeline timeline_;
  Clock::time_point host_start_ = Clock::now(), host_uploaded_, host_launched_, host_allocated_, host_pinned_,
                    host_emit_, host_done_;
  DeviceArray<double2> uploaded_points_;
  DeviceArray<int> uploaded_hull_;
  const double2* points_;
  const int* hull_;
  CellBuckets buckets_;
  DeviceArray<int> rank_, pred_;
  DeviceArray<int> star_;
  DeviceArray<std::uint32_t> info_;
  DeviceArray<int> owned_, offset_;
  // [9..11]: the edge's lists (EdgeCells); [12]: the second phase's sites that search; [13]: the
  // retry list's length after the first phase (launch_first_phase_retry).
  DeviceArray<unsigned int> counters_;
  DeviceArray<int> retry_;  // sites the first pass leaves to the retry
  DeviceArray<unsigned char> scan_temp_;
  std::optional<DeviceArray<int>> handed_on_;  // sites a light first pass hands on
  GridView g_{};
  StripBuffers strips_;
  bool exact_lattice_ = false;
  bool strip_walks_ = false;
  std::size_t full_ = 0;  // triangles of the whole triangulation, the most the device can make
  std::optional<DeviceArray<int>> triangles_, neighbors_;
  std::unique_ptr<PinnedInPlace> pinned_ = std::make_unique<PinnedInPlace>();
  bool audited_ = false;
  std::size_t open_pairs_linked_ = 0, open_edges_ = 0;
};

std::size_t scan_temp_bytes(std::size_t n, cudaStream_t stream) {
  std::size_t bytes = 0;
  EXPANSE_CUDA(cub::DeviceScan::InclusiveSum(nullptr, bytes, static_cast<int*>(nullptr), static_cast<int*>(nullptr),
                                             static_cast<int>(n), stream));
  return bytes;
}

StarRun::StarRun(Context& ctx, const GrowInput& input, GrowResult& result, const SitesOnDevice* on_device,
                 const Tuning& tuning)
    : ctx_(ctx),
      input_(input),
      result_(result),
      on_device_(on_device),
      tuning_(tuning),
      stream_(ctx.stream),
      n_(input.sites.points.size()),
      shape_(make_grid_shape(input.sites.bounds, n_, input.layout.sites_per_bucket)),
      timer_(stream_),
      timeline_(tuning.star_timeline),
      uploaded_points_(on_device ? 0 : n_, stream_),
      uploaded_hull_(on_device ? 0 : input.hull.sites.size(), stream_),
      points_(on_device ? on_device->points : uploaded_points_.get()),
      hull_(on_device ? on_device->hull : uploaded_hull_.get()),
      buckets_(n_, shape_,
               uniform_cells_shape(input.sites.bounds, n_, input.layout.sites_per_bucket,
                                   input.sites.integer_coordinates),
               tuning, stream_),
      rank_(n_, stream_),
      pred_(n_, stream_),
      star_(n_ * kStar, stream_),
      info_(n_, stream_),
      owned_(n_, stream_),
      offset_(n_ + 1, stream_),
      counters_(14, stream_),
      retry_(n_, stream_),
      scan_temp_(scan_temp_bytes(n_, stream_), stream_),
      g_(make_grid_view(shape_, input.sites.bounds)),
      strips_(buckets_.keys.get(), buckets_.ids.get(), n_),
      exact_lattice_(exact_lattice_arithmetic(input.sites)) {}

void StarRun::upload() {
  if (!on_device_) {
    timer_.begin("upload");
    static_assert(sizeof(Point2) == sizeof(double2));
    ctx_.staging->upload(uploaded_points_.get(), input_.sites.points.data(), n_ * sizeof(double2), stream_);
    ctx_.staging->upload(uploaded_hull_.get(), input_.hull.sites.data(), uploaded_hull_.bytes(), stream_);
    timer_.end();
  }
  host_uploaded_ = Clock::now();
}

void StarRun::bucket() {
  // The boundary strips (BoundaryStrips) for the searches along the grid's outer columns and
  // rows, from 2^16 sites.
  const bool strips_on = tuning_.strips == Forced::automatic ? n_ >= (std::size_t{1} << 16)
                                                             : tuning_.strips == Forced::on;
  timer_.begin("bucket");
  // The evenness test's read-back goes through pinned word 15, the guides' keys through words
  // 16..31, each read at once (the audit reuses word 15 later).
  static_assert(2 * sizeof(QuantileGuideKey) == 16 * sizeof(unsigned int));
  buckets_.build(g_, points_, static_cast<int>(n_), rank_.get(), on_device_ && on_device_->unordered_runs,
                 &ctx_.pinned_words[15], reinterpret_cast<QuantileGuideKey*>(&ctx_.pinned_words[16]),
                 &ctx_.pinned_words[14], stream_);
  apply_first_box(g_, buckets_.uniform(), input_.sites);
  // Quantile cells' outer columns copied column after column, for the searches whose boxes run
  // tall in them, where the x-axis has heavy tails (TailColumns).
  if (!buckets_.uniform() && tail_columns_wanted(buckets_.heavy_x_tails(), tuning_.tail_columns) &&
      g_.x_guide.first && g_.y_guide.first)
    build_tail_columns(g_, buckets_.keys.get(), buckets_.ids.get(), n_, stream_);
  // Strips for grids of equal cells over inputs that are no small lattice: a uniform square's
  // hull-hugging sites. Quantile cells' outer rows and columns hold a clustered input's sparse
  // tails, where the strips' scattered reads lost (kuzmin 4096^2 GPU-only 66.7 -> 69.6 ms, the
  // edge's stream 45 -> 57 ms, H100). A lattice gained nothing (its hull sides hold sites, no
  // slivers) and paid the build.
  strip_walks_ = strips_on && buckets_.uniform() && !exact_lattice_ && strips_.prepare(g_, stream_);
  EXPANSE_CUDA(cudaMemsetAsync(pred_.get(), 0xff, pred_.bytes(), stream_));
  if (!input_.hull.sites.empty()) {
    hull_predecessor_kernel<<<blocks_for(input_.hull.sites.size()), kThreads, 0, stream_>>>(
        hull_, static_cast<int>(input_.hull.sites.size()), rank_.get(), pred_.get());
    EXPANSE_CUDA(cudaGetLastError());
  }
  EXPANSE_CUDA(cudaMemsetAsync(counters_.get(), 0, counters_.bytes(), stream_));
  EXPANSE_CUDA(cudaMemsetAsync(offset_.get(), 0, sizeof(int), stream_));
  timer_.end();
}

WalkPlan StarRun::plan_walks() const {
  WalkPlan p;
  const bool integers = input_.sites.integer_coordinates;
  p.budget = tuning_.budget.value_or(box_search_budget(n_, default_budget(StarSearch::boxes)));
  p.blocks = tuning_.blocks_per_sm.value_or(default_star_blocks(n_, buckets_.uniform(), integers));
  const unsigned first_budget = tuning_.first_budget.value_or(first_pass_budget(n_, !buckets_.uniform()));
  p.two_passes = first_budget > 0 && first_budget < p.budget;
  p.light = p.two_passes && !(integers && !exact_lattice_);
  p.pass = p.two_passes ? WalkPass::first : WalkPass::only;
  p.pass_budget = p.two_passes ? first_budget : p.budget;
  p.retry_blocks = 8 * ctx_.multiprocessors;
  // The sites of the grid's outer ring of cells take their two passes on the edge stream while
  // the rest take theirs here. Only with a stream of our own (a lent stream keeps all the work).
  if (ctx_.edge_stream && p.two_passes) p.edge = EdgeCells{buckets_.keys_sorted.get(), g_.gx, g_.gy, 1};
  p.retry_budget = tuning_.retry_budget.value_or(p.edge.keys ? interior_retry_budget(p.budget) : p.budget);
  // The edge's retry on a stream of the main stream's priority, 2 blocks a multiprocessor, rather
  // than on the edge's stream of the highest: its blocks then wait for the first phase's to be
  // dispatched and run in that phase's drain and beside the second phase. Lattices keep the
  // edge's stream: no size gained.
  p.edge_retry_low = ctx_.low_stream && !exact_lattice_ && tuning_.edge_retry != Tuning::EdgeRetry::edge;
  p.edge_retry_blocks = p.edge_retry_low ? tuning_.edge_retry_blocks_per_sm * ctx_.multiprocessors : p.retry_blocks;
  p.ends_first = !buckets_.uniform();
  p.phases = tuning_.phases.value_or(n_ > (std::size_t{1} << 18) ? 2 : 1);
  p.early_retry = p.edge.keys && p.phases == 2 && p.two_passes;
  return p;
}

void StarRun::walk_stars(const WalkPlan& plan) {
  timer_.begin("stars");
  timeline_.mark("stage", stream_);  // the walks' set-up before "start"
  if (plan.light) handed_on_.emplace(n_, stream_);
  WalkArrays arrays(n_, plan, stream_);
  // Lattices are integer inputs, which run at 6 blocks a multiprocessor, and take no strips.
  if (exact_lattice_) {
    walk_passes<6, 6, 6, true, false>(plan, arrays);
  } else {
    with_star_blocks(plan.blocks.first, [&](auto first) {
      with_star_blocks(plan.blocks.later, [&](auto later) {
        with_star_blocks(plan.blocks.edge, [&](auto edge) {
          if (strip_walks_)
            walk_passes<first.value, later.value, edge.value, false, true>(plan, arrays);
          else
            walk_passes<first.value, later.value, edge.value, false, false>(plan, arrays);
        });
      });
    });
  }
  EXPANSE_CUDA(cudaGetLastError());
  timer_.end();
}

/// The edge's walks (EdgeCells) on the edge's stream, forked from the main stream: its site
/// list, its first pass (and the walks of what a light pass hands on), then its retry on the
/// low stream or its own. The strips serve the edge's walks and the warps' retry: built here,
/// beside the first phase, which needs none.
template <int EdgeB, bool Exact, bool Striped>
void StarRun::launch_edge(const WalkPlan& plan, WalkArrays& arrays, WalkEvents& events) {
  if (!plan.edge.keys) return;
  int* const sites = arrays.edge_sites();
  int* const retry = arrays.edge_retry(n_);
  int* const handed_on = arrays.edge_handed_on(n_);
  unsigned int* const counts = counters_.get() + 9;  // its sites, its retries, its handed on
  edge_list_kernel<<<blocks_for(n_), kThreads, 0, stream_>>>(plan.edge, static_cast<int>(n_), sites, counts);
  events.fork = WalkEvents::make();
  events.join = WalkEvents::make();
  EXPANSE_CUDA(cudaEventRecord(events.fork, stream_));
  EXPANSE_CUDA(cudaStreamWaitEvent(ctx_.edge_stream, events.fork));
  const cudaStream_t es = ctx_.edge_stream;
  if (strip_walks_) {
    strips_.build(g_, es);
    events.stripped = WalkEvents::make();
    EXPANSE_CUDA(cudaEventRecord(events.stripped, es));
  }
  if (plan.light) {
    star_list_kernel<EdgeB, Exact, true, false, Striped><<<plan.retry_blocks, 128, 0, es>>>(
        g_, pred_.get(), star_.get(), info_.get(), owned_.get(), counters_.get(), plan.pass_budget, sites, counts,
        retry, handed_on, counts + 1);
    star_list_kernel<EdgeB, Exact, false, false, Striped><<<plan.retry_blocks, 128, 0, es>>>(
        g_, pred_.get(), star_.get(), info_.get(), owned_.get(), counters_.get(), plan.pass_budget, handed_on,
        counts + 2, retry, nullptr, counts + 1);
  } else {
    star_list_kernel<EdgeB, Exact, false, false, Striped><<<plan.retry_blocks, 128, 0, es>>>(
        g_, pred_.get(), star_.get(), info_.get(), owned_.get(), counters_.get(), plan.pass_budget, sites, counts,
        retry, nullptr, counts + 1);
  }
  timeline_.mark("edge first pass", es);
  const cudaStream_t rs = plan.edge_retry_low ? ctx_.low_stream : es;
  if (plan.edge_retry_low) {
    events.edge_passed = WalkEvents::make();
    EXPANSE_CUDA(cudaEventRecord(events.edge_passed, es));
    EXPANSE_CUDA(cudaStreamWaitEvent(rs, events.edge_passed));
  }
  star_retry_kernel<EdgeB, Exact, Striped><<<plan.edge_retry_blocks, 128, 0, rs>>>(
      g_, pred_.get(), star_.get(), info_.get(), owned_.get(), counters_.get(), plan.budget, retry, counts + 1);
  timeline_.mark("edge retry", rs);
}

/// The first phase's retries on the edge's stream, once its own walks are done, beside the second
/// phase, which needs nothing from them: their stars post nothing (no walk posts after the first
/// phase), and the second phase searches for what they would have posted. The list as the first
/// phase leaves it (its length kept in counters[13]); the main stream's retry takes what the
/// second phase and the handed-on walks add.
template <int FirstB, bool Exact, bool Striped>
void StarRun::launch_first_phase_retry(const WalkPlan& plan, WalkEvents& events) {
  if (!plan.early_retry) return;
  copy_count_kernel<<<1, 1, 0, stream_>>>(counters_.get() + 7, counters_.get() + 13);
  events.phase0_done = WalkEvents::make();
  EXPANSE_CUDA(cudaEventRecord(events.phase0_done, stream_));
  EXPANSE_CUDA(cudaStreamWaitEvent(ctx_.edge_stream, events.phase0_done));
  star_retry_kernel<FirstB, Exact, Striped><<<plan.retry_blocks, 128, 0, ctx_.edge_stream>>>(
      g_, pred_.get(), star_.get(), info_.get(), owned_.get(), counters_.get(), plan.retry_budget, retry_.get(),
      counters_.get() + 13);
  timeline_.mark("phase 0 retry", ctx_.edge_stream);
}

/// The phases' kernels, one after the other (StarInbox): the first posts, the second records the
/// sites whose inboxes hold their whole stars (inbox_star_kernel) and walks the rest from a list.
template <class First, class LaterList>
void StarRun::walk_phases(const WalkPlan& plan, WalkArrays& arrays, First first, LaterList later_list,
                          int* handed_on, const std::function<void()>& after_phase0) {
  // The second phase's list of the sites that search lives in the triangle offsets' room
  // (offset[1..n], written only by the scan after the stars): an array of its own, 32 MB at
  // 4096^2, took the bucket stage of the next triangulation from 0.92 to 2.0 ms on uniform cells
  // (H200), the pool's placement of the bucketing's arrays most likely.
  int* const search = offset_.get() + 1;
  for (int phase = 0; phase < plan.phases; ++phase) {
    const StarInbox inbox{arrays.inbox_slots.get(), arrays.inbox_counts.get(), phase == 1};
    const std::size_t sites = (n_ - std::min<std::size_t>(n_, phase) + plan.phases - 1) / plan.phases;
    if (sites == 0) continue;
    if (phase > 0) {
      inbox_star_kernel<<<blocks_for(sites, kInboxThreads), kInboxThreads, 0, stream_>>>(
          pred_.get(), static_cast<int>(n_), star_.get(), info_.get(), owned_.get(), plan.edge, inbox, search,
          counters_.get() + 12, plan.ends_first);
      timeline_.mark("phase 1 from inboxes", stream_);
      later_list<<<blocks_for(sites, 128), 128, 0, stream_>>>(
          g_, pred_.get(), star_.get(), info_.get(), owned_.get(), counters_.get(), plan.pass_budget, search,
          counters_.get() + 12, retry_.get(), handed_on, counters_.get() + 7, plan.pass, inbox);
    } else {
      first<<<blocks_for(sites, 128), 128, 0, stream_>>>(g_, pred_.get(), static_cast<int>(n_), star_.get(),
                                                          info_.get(), owned_.get(), counters_.get(),
                                                          plan.pass_budget, plan.pass, retry_.get(), handed_on,
                                                          plan.edge, plan.phases, inbox, plan.ends_first);
    }
    timeline_.mark(phase == 0 ? "phase 0" : "phase 1", stream_);
    if (phase == 0) after_phase0();
  }
}

/// Every walk of the stars, on the main stream and (where there is one) the edge's: the edge's
/// walks, the phases' first pass, the walks of what a light first pass hands on, and the retry.
/// With_strips (Striped): the edge's walks and the warps' retry compiled with the strips' scans
/// (walk_star_boxes' Strips), where strips are built; else without (their code alone, unused,
/// slowed kuzmin's edge stream).
template <int FirstB, int LaterB, int EdgeB, bool Exact, bool Striped>
void StarRun::walk_passes(const WalkPlan& plan, WalkArrays& arrays) {
  WalkEvents events;
  timeline_.mark("start", stream_);
  if (strip_walks_ && !plan.edge.keys) strips_.build(g_, stream_);
  launch_edge<EdgeB, Exact, Striped>(plan, arrays, events);
  const std::function<void()> after_phase0 = [&] { launch_first_phase_retry<FirstB, Exact, Striped>(plan, events); };
  if (plan.light) {
    // A light first pass (no exact path, no row clipping) hands its hard sites on: each is walked
    // again here, whole, by a thread.
    int* const handed_on = handed_on_->get();
    walk_phases(plan, arrays, star_kernel<FirstB, Exact, true>, star_list_kernel<LaterB, Exact, true, true>, handed_on,
                after_phase0);
    star_list_kernel<FirstB, Exact><<<plan.retry_blocks, 128, 0, stream_>>>(
        g_, pred_.get(), star_.get(), info_.get(), owned_.get(), counters_.get(), plan.pass_budget, handed_on,
        counters_.get() + 8, retry_.get(), nullptr, counters_.get() + 7);
    timeline_.mark("handed on", stream_);
  } else {
    walk_phases(plan, arrays, star_kernel<FirstB, Exact>, star_list_kernel<LaterB, Exact, false, true>, nullptr,
                after_phase0);
  }
  if (events.stripped) EXPANSE_CUDA(cudaStreamWaitEvent(stream_, events.stripped));
  if (plan.two_passes)
    star_retry_kernel<FirstB, Exact, Striped><<<plan.retry_blocks, 128, 0, stream_>>>(
        g_, pred_.get(), star_.get(), info_.get(), owned_.get(), counters_.get(), plan.retry_budget, retry_.get(),
        counters_.get() + 7, plan.early_retry ? counters_.get() + 13 : nullptr);
  timeline_.mark("retry", stream_);
  if (plan.edge.keys) {
    EXPANSE_CUDA(cudaEventRecord(events.join, ctx_.edge_stream));
    EXPANSE_CUDA(cudaStreamWaitEvent(stream_, events.join));
    if (events.edge_passed) {
      // The same event, re-recorded after the retry: the main stream waits for it too.
      EXPANSE_CUDA(cudaEventRecord(events.edge_passed, ctx_.low_stream));
      EXPANSE_CUDA(cudaStreamWaitEvent(stream_, events.edge_passed));
    }
  }
}

void StarRun::scan() {
  timer_.begin("scan");
  std::size_t temp_bytes = scan_temp_.bytes();
  EXPANSE_CUDA(cub::DeviceScan::InclusiveSum(scan_temp_.get(), temp_bytes, owned_.get(), offset_.get() + 1,
                                             static_cast<int>(n_), stream_));
  timer_.end();
  // The one synchronisation before the output: its size (read_sizes). The words go to pinned
  // memory, so the copies stay asynchronous and the host readies the output while the device
  // works (StarSizes).
  unsigned int* const words = ctx_.pinned_words;
  EXPANSE_CUDA(cudaMemcpyAsync(&words[0], offset_.get() + n_, sizeof(int), cudaMemcpyDeviceToHost, stream_));
  EXPANSE_CUDA(cudaMemcpyAsync(&words[1], counters_.get(), 7 * sizeof(unsigned int), cudaMemcpyDeviceToHost, stream_));
}

/// The triangles and their neighbours, written where the scan put them into room for the whole
/// triangulation (the most the device can make), so that the device goes on while the host
/// readies the output: sized to the count, they waited for the host to read it (H100, 4096^2
/// uniform: the emit's 10 ms after the host's 108 ms of output allocation). Returns that room.
std::size_t StarRun::emit() {
  full_ = n_ >= 3 ? 2 * n_ - input_.hull.sites.size() - 2 : 0;
  triangles_.emplace(3 * full_, stream_);
  neighbors_.emplace(3 * full_, stream_);
  timer_.begin("emit");
  // The owned counts are scanned: their array takes each site's owned bitmask now.
  std::uint32_t* const owned_mask = reinterpret_cast<std::uint32_t*>(owned_.get());
  emit_triangles_kernel<<<blocks_for(n_, kEmitSites), kEmitSites, 0, stream_>>>(
      star_.get(), info_.get(), offset_.get(), buckets_.sorted_ids.get(), static_cast<int>(n_),
      static_cast<int>(full_), triangles_->get(), owned_mask);
  if (full_ > 0)
    emit_neighbors_kernel<<<blocks_for(full_, 128), 128, 0, stream_>>>(
        star_.get(), info_.get(), offset_.get(), owned_mask, triangles_->get(), rank_.get(), static_cast<int>(n_),
        static_cast<int>(full_), neighbors_->get());
  EXPANSE_CUDA(cudaGetLastError());
  timer_.end();
  host_launched_ = Clock::now();
  return full_;
}

/// Room for the whole triangulation (2n - h - 2) on the host, allocated while the device works:
/// the seam stage appends what deferred sites leave in place, where exactly-sized vectors would
/// have to move (805 MB at 4096^2) first. Fresh pages are faulted in on every core and zeroed
/// while the star kernel runs: done after it, this took ~460 ms at 4096^2 on the H100's host.
/// Tuning::pin_output pins it in place too, so that the download runs at the bus's speed; its
/// pages are released on another thread while the seam and output stages run
/// (GrowResult::background).
void StarRun::pin_output() {
  auto& partial = result_.partial;
  allocate_full_triangulation(partial, n_, input_.hull.sites.size(), input_.recycled);
  host_allocated_ = Clock::now();
  if (tuning_.pin_output) {
    pinned_->pin(partial.triangles.data(), partial.triangles.capacity() * sizeof(partial.triangles[0]));
    pinned_->pin(partial.neighbors.data(), partial.neighbors.capacity() * sizeof(partial.neighbors[0]));
  }
  host_pinned_ = Clock::now();
}

StarSizes StarRun::read_sizes() {
  EXPANSE_CUDA(cudaStreamSynchronize(stream_));
  StarSizes sizes;
  std::memcpy(sizes.words, ctx_.pinned_words, sizeof sizes.words);
  if (sizes.words[0] > full_)
    throw Error(ErrorCode::device_error, "CUDA backend: the stars made " + std::to_string(sizes.words[0]) +
                                             " triangles, more than a triangulation of " + std::to_string(n_) +
                                             " sites has (" + std::to_string(full_) + ")");
  return sizes;
}

/// Counts into counters[0..1] and lists up to `room` open edges (counters[2] counting).
void StarRun::run_audit_kernel(std::size_t triangle_count, std::uint64_t* open_keys, int* open_slots,
                               std::size_t room) {
  audit_kernel<<<blocks_for(triangle_count), kThreads, 0, stream_>>>(
      triangles_->get(), neighbors_->get(), static_cast<int>(triangle_count), rank_.get(), pred_.get(),
      counters_.get(), open_keys, open_slots, static_cast<unsigned>(room));
  EXPANSE_CUDA(cudaGetLastError());
}

/// The audit, on the device. Open edges inside the hull (left by deferred sites) are rare: listed
/// as the audit finds them (room for those of a few thousand deferred sites; at 4096^2: 93
/// uniform, 41 kuzmin), more by a second audit with room for all; then sorted and matched
/// against their reverses (link_open_pairs).
void StarRun::audit(std::size_t triangle_count) {
  if (triangle_count == 0) return;
  timer_.begin("audit");
  unsigned int* const words = ctx_.pinned_words;
  const std::size_t room = std::min<std::size_t>(3 * triangle_count, tuning_.audit_room);
  DeviceArray<std::uint64_t> open_keys(room, stream_), open_sorted(room, stream_);
  DeviceArray<int> slots(room, stream_), slots_sorted(room, stream_);
  EXPANSE_CUDA(cudaMemsetAsync(counters_.get(), 0, 4 * sizeof(unsigned int), stream_));
  run_audit_kernel(triangle_count, open_keys.get(), slots.get(), room);
  EXPANSE_CUDA(cudaMemcpyAsync(&words[8], counters_.get(), 2 * sizeof(unsigned int), cudaMemcpyDeviceToHost,
                               stream_));
  EXPANSE_CUDA(cudaStreamSynchronize(stream_));
  const unsigned bad = words[8], open = words[9];
  open_edges_ = open;
  audited_ = bad == 0 && open == 0;
  if (bad == 0 && open > 0)
    link_open_pairs(triangle_count, open, room, open_keys.get(), slots.get(), open_sorted.get(), slots_sorted.get());
  else if (audited_)
    result_.partial.open_slots.emplace();  // nothing open
  timer_.end();
}

/// Open edges inside the hull: listed with where they are, sorted, and the pairs linked
/// (link_open_pairs_kernel). What stays open (no reverse) is listed for the seam stage, which
/// would otherwise read all the links to find it.
void StarRun::link_open_pairs(std::size_t triangle_count, unsigned open, std::size_t room, std::uint64_t* keys,
                              int* slots, std::uint64_t* keys_sorted, int* slots_sorted) {
  unsigned int* const words = ctx_.pinned_words;
  std::optional<DeviceArray<std::uint64_t>> all_keys, all_keys_sorted;
  std::optional<DeviceArray<int>> all_slots, all_slots_sorted;
  if (open > room) {
    keys = all_keys.emplace(open, stream_).get();
    keys_sorted = all_keys_sorted.emplace(open, stream_).get();
    slots = all_slots.emplace(open, stream_).get();
    slots_sorted = all_slots_sorted.emplace(open, stream_).get();
    EXPANSE_CUDA(cudaMemsetAsync(counters_.get(), 0, 4 * sizeof(unsigned int), stream_));
    run_audit_kernel(triangle_count, keys, slots, open);
  }
  std::size_t bytes = 0;
  EXPANSE_CUDA(cub::DeviceRadixSort::SortPairs(nullptr, bytes, keys, keys_sorted, slots, slots_sorted,
                                               static_cast<int>(open), 0, 64, stream_));
  DeviceArray<unsigned char> sort_temp(bytes, stream_);
  EXPANSE_CUDA(cub::DeviceRadixSort::SortPairs(sort_temp.get(), bytes, keys, keys_sorted, slots, slots_sorted,
                                               static_cast<int>(open), 0, 64, stream_));
  // What stays open goes into `slots`, free again.
  EXPANSE_CUDA(cudaMemsetAsync(counters_.get(), 0, 4 * sizeof(unsigned int), stream_));
  link_open_pairs_kernel<<<blocks_for(open), kThreads, 0, stream_>>>(keys_sorted, slots_sorted, open,
                                                                     neighbors_->get(), counters_.get(), slots);
  EXPANSE_CUDA(cudaGetLastError());
  EXPANSE_CUDA(cudaMemcpyAsync(&words[10], counters_.get(), 4 * sizeof(unsigned int), cudaMemcpyDeviceToHost,
                               stream_));
  EXPANSE_CUDA(cudaStreamSynchronize(stream_));
  const unsigned duplicates = words[10], open_after = words[12], linked = words[13];
  audited_ = duplicates == 0 && open_after + linked == open;
  open_pairs_linked_ = linked / 2;
  if (!audited_) return;
  std::vector<int> still_open(open_after);
  EXPANSE_CUDA(cudaMemcpyAsync(still_open.data(), slots, open_after * sizeof(int), cudaMemcpyDeviceToHost, stream_));
  EXPANSE_CUDA(cudaStreamSynchronize(stream_));
  std::sort(still_open.begin(), still_open.end());  // in the atomics' order; the seam's is the triangles'
  result_.partial.open_slots.emplace(still_open.begin(), still_open.end());
}

void StarRun::download(std::size_t triangle_count) {
  host_emit_ = Clock::now();
  auto& partial = result_.partial;
  partial.triangles.resize(triangle_count);  // shrinks: no reallocation
  partial.neighbors.resize(triangle_count);
  const std::size_t bytes = 3 * triangle_count * sizeof(int);
  timer_.begin("download");
  const auto download = [&](void* host, const void* device) {
    if (pinned_->pinned(host)) {
      EXPANSE_CUDA(cudaMemcpyAsync(host, device, bytes, cudaMemcpyDeviceToHost, stream_));
    } else {
      ctx_.staging->download(host, device, bytes, stream_);
    }
  };
  download(partial.triangles.data(), triangles_->get());
  download(partial.neighbors.data(), neighbors_->get());
  timer_.end();
  EXPANSE_CUDA(cudaStreamSynchronize(stream_));
  host_done_ = Clock::now();
  if (!pinned_->empty())
    result_.background = std::async(std::launch::async, [release = std::move(pinned_)]() mutable { release.reset(); });
}

/// The run's counters and stage times into result_ and last_run_counters. The device ran the host
/// audit's checks: a failure there is final (the host would find the same, at ~300 ms for 4096^2
/// kuzmin), and the pipeline derives the adjacency instead. Edges open from both sides (both ends
/// deferred) were linked by the audit: unlinked, they failed it, and kuzmin 4096^2 spent ~600 ms
/// deriving adjacency on the host for 195 deferred sites.
void StarRun::report(const StarSizes& sizes) {
  auto& partial = result_.partial;
  const std::size_t triangle_count = sizes.words[0];
  partial.deferred_expansions = sizes.words[1];
  if (triangle_count > 0 && !audited_) partial.neighbors.clear();
  result_.adjacency_audited = audited_;
  RunCounters& counters = last_run_counters();
  counters = {};
  counters.open_pairs_linked = open_pairs_linked_;
  counters.open_edges = open_edges_;
  std::uint64_t predicates = 0;
  std::memcpy(&predicates, &sizes.words[3], sizeof predicates);
  counters.predicates = predicates;
  counters.bytes_to_device = on_device_ ? 0 : n_ * sizeof(double2) + uploaded_hull_.bytes();
  counters.bytes_to_host = 2 * 3 * triangle_count * sizeof(int) + 2 * sizeof(int);
  counters.triangles = triangle_count;
  counters.max_cells_per_site = sizes.words[5];
  counters.sites_over_4096_cells = sizes.words[6];
  counters.sites_over_budget = sizes.words[7];
  counters.uniform_cells = buckets_.uniform();
  result_.iterations = 1;
  result_.device_stages = timer_.collect();
  timeline_.print("star stage timeline (ms)");
  if (timeline_.on()) {
    // The lists' lengths beside the timeline (counters[7..12]).
    unsigned int c[13];
    EXPANSE_CUDA(cudaMemcpy(c, counters_.get(), sizeof c, cudaMemcpyDeviceToHost));
    std::fprintf(stderr,
                 "star stage lists: retry %u; handed on %u; edge %u; edge retry %u; edge handed on %u; phase 1 "
                 "search %u\n",
                 c[7], c[8], c[9], c[10], c[11], c[12]);
  }
  auto ms = [](auto a, auto b) { return std::chrono::duration<double, std::milli>(b - a).count(); };
  auto& host = result_.host_stages;
  host.push_back({"cuda upload (host)", ms(host_start_, host_uploaded_)});
  host.push_back({"cuda output allocation (host, while the device works)", ms(host_launched_, host_allocated_)});
  host.push_back({"cuda output pinning (host, while the device works)", ms(host_allocated_, host_pinned_)});
  host.push_back({"cuda device work (host wait)", ms(host_uploaded_, host_emit_) - ms(host_launched_, host_pinned_)});
  host.push_back({"cuda download (host)", ms(host_emit_, host_done_)});
}

}  // namespace

void grow_per_site(Context& ctx, const GrowInput& input, GrowResult& result, const SitesOnDevice* on_device) {
  const std::size_t n = input.sites.points.size();
  if (n >= (std::size_t{1} << 30))
    throw Error(ErrorCode::too_large, "CUDA backend: more than 2^30 sites (triangle ids would overflow)");
  // Fail early, with the right error, when the working set cannot fit.
  const GridShape shape = make_grid_shape(input.sites.bounds, n, input.layout.sites_per_bucket);
  require_device_memory(n * per_site_bytes() + static_cast<std::size_t>(shape.gx) * shape.gy * sizeof(std::uint32_t),
                        n, "sites");
  StarRun run(ctx, input, result, on_device, tuning_from_environment());
  run.upload();
  run.bucket();
  run.walk_stars(run.plan_walks());
  run.scan();
  run.emit();
  run.pin_output();
  const StarSizes sizes = run.read_sizes();
  run.audit(sizes.words[0]);
  run.download(sizes.words[0]);
  run.report(sizes);
}

}  // namespace expanse::detail::cuda
