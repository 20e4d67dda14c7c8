// The Vulkan Backend: per-site stars (default) and the paper's blocks, on any Vulkan 1.1+
// device with 64-bit floats. Host side only: bucketing, buffers, dispatch, read-back.
// Vulkan structs are value-initialised from their sType alone ({VK_STRUCTURE_TYPE_...}).
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#include "backends/vulkan/vulkan_backend.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <future>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <ranges>
#include <thread>
#include <unordered_map>
#if defined(__SSE2__)
#include <emmintrin.h>  // HostStar::find
#endif

#include "backends/backend.hpp"
#include "backends/vulkan/device_bucketing.hpp"
#include "backends/vulkan/device_preparation.hpp"
#include "backends/vulkan/shader_registry.hpp"
#include "backends/vulkan/star_cells.hpp"
#include "input/morton.hpp"
#include "input/parallel.hpp"
#include "predicates/exact_lattice.hpp"

namespace expanse::detail {
namespace vk {
namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

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

// Host threads for an O(count) pass: all of them for large passes, one for small ones.
unsigned host_workers(std::size_t count) {
  if (count < 65536) return 1;
  return std::clamp(std::thread::hardware_concurrency(), 1u, 16u);
}

// Runs body(begin, end, worker) on `workers` threads over contiguous chunks of [0, count); the
// calling thread takes the first chunk. Rethrows the first exception.
template <class Body>
void parallel_chunks(std::size_t count, unsigned workers, Body&& body) {
  workers = std::max(1u, workers);
  const std::size_t chunk = (count + workers - 1) / workers;
  std::vector<std::thread> threads;
  std::exception_ptr failure;
  std::mutex failure_mutex;
  auto run = [&](unsigned w) {
    try {
      body(std::min(count, w * chunk), std::min(count, (w + 1) * chunk), w);
    } catch (...) {
      std::lock_guard lock(failure_mutex);
      if (!failure) failure = std::current_exception();
    }
  };
  for (unsigned w = 1; w < workers; ++w) threads.emplace_back(run, w);
  run(0);
  for (auto& t : threads) t.join();
  if (failure) std::rethrow_exception(failure);
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

struct GridParams {
  double origin[2];
  double inv_width[2];
  std::int32_t cells;
  std::int32_t count;
  std::int32_t first;
  std::int32_t triangle_capacity;
};
static_assert(sizeof(GridParams) == 48);

// star.comp's push constants: the grid, then the scan size that counts as large.
struct StarParams {
  GridParams grid;
  std::int32_t big_scan_cells;
  std::int32_t pass;       // the class of sites this dispatch walks
  std::int32_t pass_mask;  // classes - 1
  std::int32_t pass_shift;  // log2 of the runs of consecutive ids in one class
};
static_assert(sizeof(StarParams) == 64);

// audit.comp's push constants.
struct AuditParams {
  std::int32_t triangle_capacity;
  std::int32_t open_capacity;
  std::int32_t first;
  std::int32_t pad;
};
static_assert(sizeof(AuditParams) == 16);
// counters[] words audit.comp sets: bad links, open edges inside the hull, open edges not listed.
constexpr std::size_t bad_link_counter = 10, open_edge_counter = 11, open_overflow_counter = 12;

struct LinkParams {
  std::int32_t count;
  std::int32_t first;
  std::int32_t unresolved_capacity;
  std::int32_t pad;
};
static_assert(sizeof(LinkParams) == 16);

// Star row length on the device (shaders/star.comp, STAR_CAPACITY): longer stars defer.
constexpr std::uint32_t star_capacity = 16;
static_assert(star_capacity <= 16, "star_common.glsl packs star positions and owned masks in 4 and 16 bits");

VkDeviceSize bytes_of(std::size_t count, std::size_t size) { return VkDeviceSize(count) * size; }

// memcpy in one sequential stream per host thread: the access pattern write-combined (uncached)
// mapped memory needs, and page faults of a fresh destination spread over the cores.
void copy_on_host_threads(void* to, const void* from, std::size_t bytes) {
  detail::parallel_chunks(bytes, detail::chunk_count(bytes, std::size_t(1) << 20),
                          [&](std::size_t, std::size_t begin, std::size_t end) {
                            std::memcpy(static_cast<char*>(to) + begin,
                                        static_cast<const char*>(from) + begin, end - begin);
                          });
}

// The host's part of the device audit (audit.comp checked every link the device made and
// listed the open slots, edges inside the hull with no link): the links pair_unresolved made
// on the host lead to the reverse edge and back, and no edge left open has its reverse open
// too, as seam/adjacency_audit.cpp's second check. Costs the seam's size, not the mesh's.
bool open_edges_check_out(const std::vector<std::int32_t>& open_slots,
                                 const std::vector<std::int32_t>& paired_slots,
                                 const PartialTriangulation& partial) {
  const std::size_t count = partial.triangles.size();
  auto edge_at = [&](std::int32_t slot, std::int32_t& x, std::int32_t& y) {
    const Triangle& t = partial.triangles[std::size_t(slot / 3)];
    x = t[std::size_t((slot % 3 + 1) % 3)];
    y = t[std::size_t((slot % 3 + 2) % 3)];
  };
  auto key = [](std::int32_t x, std::int32_t y) {
    return (std::uint64_t(std::uint32_t(x)) << 32) | std::uint32_t(y);
  };
  std::unordered_map<std::uint64_t, int> still_open;
  for (const auto* list : {&open_slots, &paired_slots}) {
    for (std::int32_t slot : *list) {
      if (slot < 0 || std::size_t(slot / 3) >= count) return false;
      const std::int32_t u = partial.neighbors[std::size_t(slot / 3)][std::size_t(slot % 3)];
      std::int32_t x, y;
      edge_at(slot, x, y);
      if (u == no_neighbor) {
        still_open.emplace(key(x, y), 0);
        continue;
      }
      if (u < 0 || std::size_t(u) >= count) return false;
      const Triangle& other = partial.triangles[std::size_t(u)];
      int j = 0;
      while (j < 3 && !(other[std::size_t((j + 1) % 3)] == y && other[std::size_t((j + 2) % 3)] == x)) ++j;
      if (j == 3 || partial.neighbors[std::size_t(u)][std::size_t(j)] != slot / 3) return false;
    }
  }
  for (const auto& [edge, unused] : still_open)
    if (still_open.count((edge << 32) | (edge >> 32))) return false;
  return true;
}

// Records audit.comp over the first counters[0] (at most `capacity`) triangles, in SiteSet ids,
// and their links; `predecessor` is hull.predecessor. Binds the kernel: between submissions only.
void record_audit(Context& ctx, Recording& rec, std::uint32_t wg, Buffer& triangles,
                  Buffer& neighbors, Buffer& predecessor, Buffer& open_slots, Buffer& counters,
                  std::size_t capacity, std::size_t open_capacity) {
  const std::uint32_t audit_spec[] = {wg};
  Kernel& audit = ctx.kernel("audit", spirv::audit(), 5, sizeof(AuditParams), audit_spec);
  Buffer* bindings[] = {&triangles, &neighbors, &predecessor, &open_slots, &counters};
  audit.bind(bindings);
  AuditParams params{std::int32_t(capacity), std::int32_t(open_capacity), 0, 0};
  const std::uint64_t max_groups = ctx.limits().maxComputeWorkGroupCount[0];
  for (std::uint64_t first = 0; first < capacity; first += max_groups * wg) {
    params.first = std::int32_t(first);
    const std::uint64_t left = (capacity - first + wg - 1) / wg;
    rec.dispatch(audit, &params, std::uint32_t(std::min(left, max_groups)));
  }
  rec.barrier();
}

/// A cells x cells grid over the sites' bounding box (cell_coord's origin and scale).
struct GridFrame {
  int cells = 0;
  double origin[2]{}, inv_width[2]{};

  GridFrame() = default;
  GridFrame(const SiteSet& sites, int cells_per_side) : cells(cells_per_side) {
    origin[0] = sites.bounds.min_x;
    origin[1] = sites.bounds.min_y;
    const double wx = sites.bounds.max_x - sites.bounds.min_x;
    const double wy = sites.bounds.max_y - sites.bounds.min_y;
    inv_width[0] = wx > 0 ? double(cells) / wx : 0.0;
    inv_width[1] = wy > 0 ? double(cells) / wy : 0.0;
  }
};

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
    if (input.layout.seeding == Layout::Seeding::paper_blocks)
      grow_blocks(input, result);
    else
      grow_stars(input, result);
    context_->instance().throw_if_messages(messages);
    return result;
  }

  // Where the per-site layout's sites are prepared (scaled, in Morton order, duplicates merged).
  // On a GPU, on the device (prepare_sites.comp, radix_sort.comp): on the H100's host,
  // prepare_sites took 117-184 ms at 4096^2 on 16 threads, about as long as the device's whole
  // growth (session 8). On a CPU device (lavapipe), on the host: the shaders would run on the
  // same cores as prepare_sites' native code. EXPANSE_VULKAN_PREPARE=host or =device overrides
  // (the tests run the device's preparation on lavapipe).
  bool prepares_sites(const Layout& layout) const override {
    if (layout.seeding == Layout::Seeding::paper_blocks) return false;
    const char* where = std::getenv("EXPANSE_VULKAN_PREPARE");
    if (where && std::strcmp(where, "host") == 0) return false;
    if (where && std::strcmp(where, "device") == 0) return true;
    return !cpu_device();
  }

  std::optional<InputGrowResult> grow_from_input(const InputGrowInput& input) override {
    if (!prepares_sites(input.layout)) return std::nullopt;
    std::lock_guard lock(context_->mutex());
    const std::size_t messages = context_->instance().message_count();
    std::optional<InputGrowResult> result(std::in_place);
    SiteCopy copy(*context_);
    if (!prepare_on_device(input, *result, copy)) return std::nullopt;
    const std::size_t m = std::size_t(result->sites.size());
    // Device predicates need every nonzero coordinate at least 2^-200 (device_safe): else the
    // exact CPU stage does it all, as grow() leaves it.
    if (input.scan.smallest_nonzero < 0x1p-200) {
      copy.start();
      copy.finish();
      result->grown.partial.deferred_expansions = m;
    } else {
      grow_stars(GrowInput{result->sites, result->hull, input.layout, input.recycled}, result->grown, &copy);
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
  struct Sorted : GridFrame {
    std::vector<Point2> points;            // sites sorted by cell (row-major)
    std::vector<std::int32_t> to_site;     // sorted id -> SiteSet id
    std::vector<std::int32_t> predecessor; // in sorted ids
    std::vector<std::int32_t> cell_start;  // cells^2 + 1
    std::vector<std::int32_t> cell_of;     // sorted id -> cell
  };

  static Sorted bucket(const GrowInput& input, int cells) {
    const SiteSet& sites = input.sites;
    const std::size_t n = std::size_t(sites.size());
    Sorted s;
    static_cast<GridFrame&>(s) = GridFrame(sites, cells);
    std::vector<std::int32_t> cell(n);
    s.cell_start.assign(std::size_t(cells) * std::size_t(cells) + 1, 0);
    for (std::size_t i = 0; i < n; ++i) {
      const Point2& p = sites.points[i];
      const int cx = cell_coord(p.x, s.origin[0], s.inv_width[0], cells);
      const int cy = cell_coord(p.y, s.origin[1], s.inv_width[1], cells);
      cell[i] = cy * cells + cx;
      ++s.cell_start[std::size_t(cell[i]) + 1];
    }
    for (std::size_t c = 1; c < s.cell_start.size(); ++c) s.cell_start[c] += s.cell_start[c - 1];
    std::vector<std::int32_t> fill(s.cell_start.begin(), s.cell_start.end() - 1);
    std::vector<std::int32_t> to_sorted(n);
    s.to_site.resize(n);
    s.points.resize(n);
    s.cell_of.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      const std::int32_t at = fill[std::size_t(cell[i])]++;
      to_sorted[i] = at;
      s.to_site[std::size_t(at)] = std::int32_t(i);
      s.points[std::size_t(at)] = sites.points[i];
      s.cell_of[std::size_t(at)] = cell[i];
    }
    s.predecessor.resize(n);
    for (std::size_t k = 0; k < n; ++k) {
      const std::int32_t p = input.hull.predecessor[std::size_t(s.to_site[k])];
      s.predecessor[k] = p < 0 ? -1 : to_sorted[std::size_t(p)];
    }
    return s;
  }

  static void finish(const Sorted& s, const std::vector<std::int32_t>& raw, std::size_t count,
                     GrowResult& result) {
    auto& triangles = result.partial.triangles;
    triangles.resize(count);
    const std::size_t n = s.to_site.size();
    for (std::size_t t = 0; t < count; ++t)
      for (int k = 0; k < 3; ++k) {
        const std::int32_t id = raw[3 * t + std::size_t(k)];
        if (id < 0 || std::size_t(id) >= n)
          throw Error(ErrorCode::internal, "Vulkan: the device returned site id " +
                                               std::to_string(id) + " of " + std::to_string(n));
        triangles[t][std::size_t(k)] = s.to_site[std::size_t(id)];
      }
  }

  // lavapipe breaks out of every loop after 65535 iterations per SIMD batch (8 lanes); a lane
  // budget of 1000 keeps the batch under that cap (the shaders also check a canary). In
  // star.comp every pass of each of its five loops spends from the budget of a lane taking it,
  // so a batch makes at most 5 x 8 x 1000 back-edges; a site needs about 120 (1M
  // uniform), and the ~0.07% that would need more are cheaper in the seam stage: 2000 cut the
  // deferrals by a quarter but cost more device time than the seam saved. On GPUs a
  // star walk still gets a budget, 20,000 units: the kernel lasts as long as its slowest
  // invocation, and the rare walk that would scan half the grid is cheaper in the seam stage.
  // Measured on the H100 against 65,536 (2026-11-23, one run, two rounds, medians of 5, uniform
  // 256^2 / 512^2 / 1024^2 / 2048^2 / 4096^2): star shader 6.2 / 11.2 / 15.3 / 31 / 80 ms
  // against 19 / 37 / 37 / 46 / 108, host to host 16 / 29 / 44 / 101-122 / 329-398 against
  // 27-30 / 54-56 / 65 / 121-125 / 336-364 (cuda_backend/results/2026-11-23-h100-s5, call 6).
  // EXPANSE_VULKAN_LOOP_BUDGET overrides it (for experiments).
  std::uint32_t loop_budget(bool star) const {
    if (const char* env = std::getenv("EXPANSE_VULKAN_LOOP_BUDGET"))
      return std::uint32_t(std::max(1L, std::atol(env)));
    if (context_->physical().properties.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU) return 1000u;
    return star ? 20000u : 1000000000u;
  }

  // star.comp's passes: classes of sites walked one after another, each taking the triangles it
  // shares with earlier classes from what their stars posted to it. Four classes of single ids
  // on CPU devices: lavapipe, 1M uniform, star shader 755-802 -> 553-560 ms (this VM,
  // 2026-11-25; two 586-599, eight 590-604), when a later class still read the stars that
  // listed themselves; posts took it to 529-538 ms against 583-592, kuzmin's unchanged at
  // 1379-1444 (alternated, session 15). One class on GPUs: on the H100, two classes with posts
  // (each its own light pass and edge ring) took 4096^2 uniform's star shader from 54.4 to
  // 46.7 ms, but kuzmin's from 106 to 111 and 1024^2 uniform's from 12.5 to 20.6
  // (cuda_backend/results/2026-11-25-h100-s15, call 11).
  // EXPANSE_VULKAN_STAR_PASSES (1, 2, 4, 8, 16) overrides, for experiments.
  std::uint64_t star_passes() const {
    if (const char* env = std::getenv("EXPANSE_VULKAN_STAR_PASSES")) {
      const long k = std::atol(env);
      if (k >= 1 && k <= 16 && (k & (k - 1)) == 0) return std::uint64_t(k);
    }
    return cpu_device() ? 4 : 1;
  }
  // In one class (GPUs), walk the stars in a light pass without the exact path and retry the
  // sites it hands on (star.comp's EXACT_PATH, RETRY). EXPANSE_VULKAN_LIGHT_PASS=0 walks them in
  // one full pass, for comparisons.
  static bool light_first_pass() {
    const char* env = std::getenv("EXPANSE_VULKAN_LIGHT_PASS");
    return !(env && env[0] == '0');
  }
  // EXPANSE_VULKAN_EDGE=0: one dispatch for every site's first walk, not the grid's outer ring
  // of cells apart (star.comp's EDGE_PART), for comparisons.
  static bool edge_first() {
    const char* env = std::getenv("EXPANSE_VULKAN_EDGE");
    return !(env && std::strcmp(env, "0") == 0);
  }
  // log2 of the runs of consecutive ids in one class; EXPANSE_VULKAN_CLASS_SHIFT overrides.
  static int star_class_shift() {
    if (const char* env = std::getenv("EXPANSE_VULKAN_CLASS_SHIFT")) return std::clamp(std::atoi(env), 0, 10);
    return 0;
  }

  // star.comp's APEX_FILTERS: the filters in the edge's frame on CPU devices (lavapipe: star
  // shader -7% at 1M uniform), the filters on the points elsewhere (the H100's driver: +6% with
  // the apex filters). EXPANSE_VULKAN_APEX_FILTERS=0/1 overrides, for experiments.
  std::uint32_t apex_filters() const {
    if (const char* env = std::getenv("EXPANSE_VULKAN_APEX_FILTERS")) return std::atoi(env) != 0;
    return context_->physical().properties.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU;
  }

  // star.comp's EXACT_LATTICE, for small integer lattices (exact_lattice.hpp): their ties
  // decided in the scan, not the exact loop. The perturbation there is branch-free
  // (cocircular_perturbed_lattice): with the loops of the general one, lavapipe's masked lanes
  // ran it for every candidate and its 1M lattice star shader went from 1.30 to 2.37 s; now
  // 1.27-1.28 -> 0.65-0.68 s; NVIDIA 4096^2: 52.0 -> 23.3 ms (session 8, call 14).
  // EXPANSE_VULKAN_EXACT_LATTICE=0 takes lattices through the exact loop (comparisons, tests).
  static bool exact_lattice_search() {
    const char* env = std::getenv("EXPANSE_VULKAN_EXACT_LATTICE");
    return !(env && std::strcmp(env, "0") == 0);
  }

  // EXPANSE_VULKAN_WORKGROUP: invocations per workgroup of the per-site kernels (experiments).
  static std::uint32_t star_workgroup_override() {
    const char* env = std::getenv("EXPANSE_VULKAN_WORKGROUP");
    return env ? std::uint32_t(std::max(0L, std::atol(env))) : 0u;
  }

  std::uint32_t workgroup(std::uint32_t wanted) const {
    const auto& limits = context_->limits();
    return std::max(1u, std::min({wanted, limits.maxComputeWorkGroupSize[0],
                                  limits.maxComputeWorkGroupInvocations}));
  }

  // Sites sorted by cell for the star kernel, written straight into `points`, `cell_start` and
  // `predecessor` (mapped memory: the device's own on unified-memory devices, else staging).
  // A counting sort in O(n + cells), its passes split over the host threads; sites keep their
  // SiteSet order within a cell, so the result does not depend on the thread count.
  struct StarGrid {
    std::vector<std::int32_t> to_site;  // sorted id -> SiteSet id
  };

  static StarGrid bucket_stars(const GrowInput& input, const StarCells& plan, Point2* points,
                               std::int32_t* cell_start, std::int32_t* predecessor) {
    const SiteSet& sites = input.sites;
    const std::size_t n = std::size_t(sites.size());
    const int cells = plan.cells;
    StarGrid g;
    const std::size_t cell_count = std::size_t(cells) * std::size_t(cells);
    // Each worker counts into its own array of all cells: at most 2^24 counts in all (64 MB).
    const unsigned workers = unsigned(std::clamp<std::size_t>(
        (std::size_t(1) << 24) / std::max<std::size_t>(cell_count, 1), 1, host_workers(n)));
    std::vector<std::int32_t> cell(n);
    std::vector<std::vector<std::int32_t>> fill(workers);
    parallel_chunks(n, workers, [&](std::size_t begin, std::size_t end, unsigned w) {
      fill[w].assign(cell_count, 0);  // zeroed (first touched) by the thread that counts in it
      std::int32_t* count = fill[w].data();
      for (std::size_t i = begin; i < end; ++i) {
        const Point2& p = sites.points[i];
        cell[i] = plan.y(p.y) * cells + plan.x(p.x);
        ++count[cell[i]];
      }
    });
    // cell_start, and each worker's first slot in each cell: a prefix sum over cells (then
    // workers), in two parallel passes over ranges of cells.
    std::vector<std::int32_t> range_sum(workers + 1, 0);
    parallel_chunks(cell_count, workers, [&](std::size_t begin, std::size_t end, unsigned r) {
      std::int32_t sum = 0;
      for (std::size_t c = begin; c < end; ++c)
        for (unsigned w = 0; w < workers; ++w) sum += fill[w][c];
      range_sum[r + 1] = sum;
    });
    for (unsigned r = 0; r < workers; ++r) range_sum[r + 1] += range_sum[r];
    parallel_chunks(cell_count, workers, [&](std::size_t begin, std::size_t end, unsigned r) {
      std::int32_t running = range_sum[r];
      for (std::size_t c = begin; c < end; ++c) {
        cell_start[c] = running;
        for (unsigned w = 0; w < workers; ++w) {
          const std::int32_t here = fill[w][c];
          fill[w][c] = running;
          running += here;
        }
      }
    });
    cell_start[cell_count] = std::int32_t(n);
    std::vector<std::int32_t> to_sorted(n);
    g.to_site.resize(n);
    parallel_chunks(n, workers, [&](std::size_t begin, std::size_t end, unsigned w) {
      std::int32_t* next = fill[w].data();
      for (std::size_t i = begin; i < end; ++i) {
        const std::int32_t at = next[cell[i]]++;
        to_sorted[i] = at;
        g.to_site[std::size_t(at)] = std::int32_t(i);
        points[at] = sites.points[i];
      }
    });
    parallel_chunks(n, workers, [&](std::size_t begin, std::size_t end, unsigned) {
      for (std::size_t k = begin; k < end; ++k) {
        const std::int32_t p = input.hull.predecessor[std::size_t(g.to_site[k])];
        predecessor[k] = p < 0 ? -1 : to_sorted[std::size_t(p)];
      }
    });
    return g;
  }

  // The per-site layout's buffers, kept between calls by the context (BufferCache): every
  // Backend on it shares them, so the free function expanse::triangulate, which makes a
  // Backend per call, allocates nothing after its first call either (allocating them cost
  // 325-365 ms at 4096^2 on the H100, on every call). Host-visible only where a CPU device
  // works in place; GPUs stage through the context's fixed StagingRing.
  enum Kept : std::size_t {
    k_input_sites, k_input_predecessor, k_cell_key, k_cursor, k_unordered, k_to_sorted,
    k_scan_sums, k_sites, k_cell_start, k_predecessor, k_to_site, k_triangles, k_counters,
    k_stars, k_site_info, k_neighbors, k_unresolved, k_open_slots, k_words,
    // The preparation's (device_preparation.hpp); it leaves the sites in k_input_sites and the
    // hull predecessors in k_input_predecessor.
    k_prep_raw, k_prep_keys0, k_prep_keys1, k_prep_values0, k_prep_values1, k_prep_sorted,
    k_prep_first, k_prep_heads, k_prep_head_sums, k_prep_counts, k_prep_count_sums,
    k_prep_site_input, k_prep_rank, k_prep_representative, k_prep_hull_input, k_prep_hull_sites,
    k_prep_counters, k_cell_bounds, k_sites_to_host
  };
  Buffer& kept(Kept slot, VkDeviceSize bytes, bool host_visible) {
    return context_->buffers().get(slot, bytes, host_visible);
  }

  // Where the star grid's sites are sorted into cells. On a GPU, on the device (bucket.comp):
  // host-visible memory there is uncached, and the host's scattered writes into it were the
  // slowest stage (532 ms at 4096^2 on the H100). On a CPU device (lavapipe), on the host: its
  // counting sort writes the buffers in place, and took 17 ms at 10^6 where bucket.comp took
  // 200 ms and mapping the ids back 190 ms (this VM, 2026-11-23). EXPANSE_VULKAN_BUCKET=host or
  // =device overrides (the tests run both on lavapipe).
  static bool bucket_on_device(bool cpu_device) {
    const char* where = std::getenv("EXPANSE_VULKAN_BUCKET");
    if (where && std::strcmp(where, "host") == 0) return false;
    if (where && std::strcmp(where, "device") == 0) return true;
    return !cpu_device;
  }

  // The host's counting sort (bucket_stars), straight into the star kernel's buffers when they
  // are host-visible (in place), else into host memory that the staging ring uploads (the
  // star kernel's recording starts with a barrier, which orders it after those copies). Used
  // on CPU devices, and where a cell is too crowded for the device's ranking (bucket.comp,
  // MAX_CELL).
  void bucket_on_host(const GrowInput& input, const StarCells& plan, Buffer& sites, Buffer& cell_start,
                      Buffer& predecessor, StarGrid& grid) {
    const std::size_t n = std::size_t(input.sites.size());
    const std::size_t cell_entries = std::size_t(plan.cells) * std::size_t(plan.cells) + 1;
    if (sites.mapped() && cell_start.mapped() && predecessor.mapped()) {
      grid = bucket_stars(input, plan, static_cast<Point2*>(sites.mapped()),
                          static_cast<std::int32_t*>(cell_start.mapped()),
                          static_cast<std::int32_t*>(predecessor.mapped()));
      return;
    }
    std::vector<Point2> points(n);
    std::vector<std::int32_t> starts(cell_entries), predecessors(n);
    grid = bucket_stars(input, plan, points.data(), starts.data(), predecessors.data());
    const StagingRing::Upload pieces[] = {
        {points.data(), sites.handle(), 0, bytes_of(n, 16)},
        {starts.data(), cell_start.handle(), 0, bytes_of(cell_entries, 4)},
        {predecessors.data(), predecessor.handle(), 0, bytes_of(n, 4)}};
    context_->staging().upload(pieces);
  }

  // Device triangles (sorted ids) -> partial.triangles (SiteSet ids, room already made),
  // checking every id: the host's twin of bucket.comp's restore pass, when the host bucketed.
  static void restore_on_host(const StarGrid& g, const std::int32_t* raw, std::size_t count,
                              PartialTriangulation& partial) {
    const std::size_t n = g.to_site.size();
    std::atomic<bool> bad{false};
    parallel_chunks(count, host_workers(count), [&](std::size_t begin, std::size_t end, unsigned) {
      for (std::size_t t = begin; t < end; ++t)
        for (std::size_t k = 0; k < 3; ++k) {
          const std::int32_t id = raw[3 * t + k];
          if (id < 0 || std::size_t(id) >= n) {
            bad = true;
            return;
          }
          partial.triangles[t][k] = g.to_site[std::size_t(id)];
        }
    });
    if (bad) throw Error(ErrorCode::internal, "Vulkan: the device returned an invalid site id");
  }

  bool cpu_device() const {
    return context_->physical().properties.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU;
  }

  // A CPU device (lavapipe) runs on host memory: its buffers are written and read in place,
  // with no staging copies, and the adjacency is derived from the stars on the host, where
  // pointer chasing costs a load instead of a loop over the SIMD lanes. EXPANSE_VULKAN_STAGED=1
  // takes the GPU path on any device (staging copies, star_links.comp): the tests use it to
  // run that path on lavapipe.
  bool works_in_place() const {
    const char* staged = std::getenv("EXPANSE_VULKAN_STAGED");
    return cpu_device() && !(staged && std::strcmp(staged, "0") != 0 && *staged);
  }

  // The prepared sites, their input indices and (where points repeat) the representatives,
  // copied to the host while the stars grow: one submission of copies into a kept host-visible
  // buffer, untimed (the timed star submission owns the query pool), then the host's copy out
  // of it on another thread. On the H100 the copy through the ring before the growth took
  // 24-26 ms of 229-261 at 4096^2 (session 9, call 2).
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

    void start() {
      if (rec || pieces.empty()) return;
      rec.emplace(ctx, /*timed=*/false);
      rec->barrier_after_compute();
      VkDeviceSize at = 0;
      for (const Piece& piece : pieces) {
        rec->copy(*piece.from, *staging, piece.bytes, 0, at);
        at += piece.bytes;
      }
      rec->barrier_to_host();
      rec->submit_only();
      host = std::async(std::launch::async, [this] {
        rec->wait();
        const auto begin = Clock::now();
        // Threads of its own: the host's shared pool runs one job at a time, and meanwhile it
        // readies the output vectors (a second job runs on its caller alone: 75-93 ms for these
        // 320 MB at 4096^2 on the H100's host, session 9 call 3).
        const char* from = static_cast<const char*>(staging->mapped());
        for (const Piece& piece : pieces) {
          vk::parallel_chunks(std::size_t(piece.bytes), host_workers(std::size_t(piece.bytes) >> 6),
                              [&](std::size_t first, std::size_t last, unsigned) {
                                std::memcpy(static_cast<char*>(piece.to) + first, from + first, last - first);
                              });
          from += piece.bytes;
        }
        host_ms = ms_since(begin);
      });
    }
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

  // The raw input prepared on the device (device_preparation.hpp), as prepare_sites and
  // convex_hull would have made it for the rest of the pipeline: the sites and their input
  // indices, the representatives and the hull come back to the host (the seam stage and the
  // output need them); the sites and the hull predecessors stay in k_input_sites and
  // k_input_predecessor for grow_stars. False, with nothing consumed, when the device cannot
  // (too large for its buffers) or the hull is degenerate: the host prepares instead.
  bool prepare_on_device(const InputGrowInput& input, InputGrowResult& result,
                         SiteCopy& copy) {
    Context& ctx = *context_;
    const std::size_t n = input.points.size();
    if (n >= (std::size_t{1} << 30) || bytes_of(n, 16) > ctx.max_buffer_bytes()) return false;
    const InputScan& scan = input.scan;
    const Quantiser quantiser(scan.bounds);
    PreparationScale scale;
    scale.origin[0] = quantiser.origin_x;
    scale.origin[1] = quantiser.origin_y;
    scale.scale = quantiser.scale;
    if (scan.scale_exponent <= 1023) {
      scale.factor = scan.factor;
    } else {  // past 2^1023 (subnormal input): two exact steps, as ldexp's one
      scale.factor = 0x1p1000;
      scale.second_factor = std::ldexp(1.0, scan.scale_exponent - 1000);
    }

    // Every point its own representative, written on another host thread while the device
    // works (the usual case; the device's map replaces it where points repeat).
    SiteSet& sites = result.sites;
    auto identity = std::async(std::launch::async, [&sites, n] {
      auto& representative = sites.representative;
      representative.reserve(n);
      advise_huge_pages(representative.data(), n * sizeof(std::int32_t));
      const auto ids = std::views::iota(std::int32_t{0}, std::int32_t(n));
      representative.assign(ids.begin(), ids.end());
    });
    auto& host = result.grown.host_stages;
    auto& device = result.grown.device_stages;
    const bool in_place = works_in_place();
    DevicePreparation prep(ctx, workgroup(64));
    Buffer& counters = kept(k_prep_counters, 64, false);
    Buffer& words = kept(k_words, 64, true);
    PreparationBuffers buffers{&kept(k_prep_raw, bytes_of(n, 16), false),
                               {&kept(k_prep_keys0, bytes_of(n, 8), false), &kept(k_prep_keys1, bytes_of(n, 8), false)},
                               {&kept(k_prep_values0, bytes_of(n, 4), false), &kept(k_prep_values1, bytes_of(n, 4), false)},
                               &kept(k_prep_sorted, bytes_of(n, 16), false),
                               &kept(k_prep_first, bytes_of(n, 4), false),
                               &kept(k_prep_heads, bytes_of(n, 4), false),
                               &kept(k_prep_head_sums, prep.head_sums_bytes(n), false),
                               &kept(k_prep_counts, prep.counts_bytes(n), false),
                               &kept(k_prep_count_sums, prep.count_sums_bytes(n), false),
                               &kept(k_input_sites, bytes_of(n, 16), in_place),
                               &kept(k_prep_site_input, bytes_of(n, 4), false),
                               &kept(k_prep_rank, bytes_of(n, 4), false),
                               &kept(k_prep_representative, bytes_of(n, 4), false),
                               &counters,  // the hull's buffers, bound once it is known
                               &counters,
                               &kept(k_input_predecessor, bytes_of(n, 4), in_place),
                               &counters};
    prep.bind(buffers);

    auto start = Clock::now();
    const StagingRing::Upload raw[] = {{input.points.data(), buffers.raw->handle(), 0, bytes_of(n, 16)}};
    ctx.staging().upload(raw);
    host.push_back({"vulkan: upload of the input", ms_since(start)});

    start = Clock::now();
    std::uint32_t word[16];
    const auto submit = [&](auto&& record) {
      Recording rec(ctx);
      rec.barrier();  // after the ring's copies
      record(rec);
      rec.copy(counters, words, 64);
      rec.barrier_to_host();
      for (StageTime& stage : rec.submit()) device.push_back(std::move(stage));
      std::memcpy(word, words.mapped(), sizeof(word));
    };
    submit([&](Recording& rec) {
      prep.record_sort(rec, n, scale);
      rec.timestamp("vulkan: prepare (sort)");
      prep.record_compact(rec, n);
      rec.timestamp("vulkan: prepare (merge)");
    });
    if (word[long_run_counter] != 0) {
      // A run of equal codes too long to search pairwise (many copies of a point, or a cluster
      // finer than the quantisation): sorted again by (code, x, y), equal points side by side.
      submit([&](Recording& rec) {
        prep.record_sort_by_point(rec, n);
        rec.timestamp("vulkan: prepare (sort by point)");
        prep.record_compact(rec, n);
        rec.timestamp("vulkan: prepare (merge)");
      });
    }
    const std::size_t m = word[site_count_counter];
    host.push_back({"vulkan: prepare on the device (submit + wait)", ms_since(start)});
    if (m < 1 || m > n) throw Error(ErrorCode::internal, "Vulkan: the device's preparation counted " + std::to_string(m) + " sites");

    start = Clock::now();
    const std::vector<std::int32_t>* hull_input = input.hull();
    host.push_back({"vulkan: wait for the host's hull", ms_since(start)});
    if (!hull_input) return false;  // collinear: the host's path handles it
    start = Clock::now();
    const std::size_t h = hull_input->size();
    buffers.hull_input = &kept(k_prep_hull_input, bytes_of(h, 4), false);
    buffers.hull_sites = &kept(k_prep_hull_sites, bytes_of(h, 4), false);
    prep.bind(buffers);
    const StagingRing::Upload hull_upload[] = {{hull_input->data(), buffers.hull_input->handle(), 0, bytes_of(h, 4)}};
    ctx.staging().upload(hull_upload);
    // The grid's sample of the sites (star_cells.hpp) into the sorted points' buffer, free now.
    const std::size_t stride = star_cell_sample_stride(m), samples = m / stride;
    submit([&](Recording& rec) {
      prep.record_hull(rec, h);
      prep.record_sample(rec, samples, stride);
      rec.timestamp("vulkan: prepare (hull, sample)");
    });

    // What the host needs before the growth: the hull and the sample. The sites, their input
    // indices and the representatives follow while the stars grow (SiteCopy).
    sites.scale_exponent = scan.scale_exponent;
    sites.integer_coordinates = scan.integer_coordinates;
    sites.bounds = scan.bounds;
    resize_for_parallel_write(sites.points, m);
    resize_for_parallel_write(sites.input_index, m);
    Hull& hull = result.hull;
    hull.sites.resize(h);
    copy.sample_points.resize(samples);
    const StagingRing::Download pieces[] = {
        {buffers.hull_sites->handle(), 0, hull.sites.data(), bytes_of(h, 4)},
        {buffers.sorted->handle(), 0, copy.sample_points.data(), bytes_of(samples, 16)}};
    ctx.staging().download(pieces);
    identity.get();
    copy.staging = &kept(k_sites_to_host, bytes_of(m, 20) + (m < n ? bytes_of(n, 4) : 0), true);
    copy.pieces = {{buffers.site_points, sites.points.data(), bytes_of(m, 16)},
                   {buffers.site_input, sites.input_index.data(), bytes_of(m, 4)}};
    if (m < n) copy.pieces.push_back({buffers.representative, sites.representative.data(), bytes_of(n, 4)});
    resize_for_parallel_write(hull.predecessor, m);
    detail::parallel_chunks(m, [&](std::size_t, std::size_t begin, std::size_t end) {
      std::fill(hull.predecessor.begin() + std::ptrdiff_t(begin), hull.predecessor.begin() + std::ptrdiff_t(end), -1);
    });
    for (std::size_t k = 0; k < h; ++k) {
      const std::int32_t site = hull.sites[k];
      if (site < 0 || std::size_t(site) >= m) throw Error(ErrorCode::internal, "Vulkan: the device mapped a hull site out of range");
      hull.predecessor[std::size_t(site)] = hull.sites[(k + h - 1) % h];
    }
    host.push_back({"vulkan: hull and the grid's sample to the host", ms_since(start)});
    return true;
  }

  // From prepare_on_device (site_copy not null): the sites are in k_input_sites and the hull
  // predecessors in k_input_predecessor (nothing to upload for the device's bucketing), and on
  // the host only their sample until site_copy has run, which this starts beside the stars.
  void grow_stars(const GrowInput& input, GrowResult& result, SiteCopy* site_copy = nullptr) {
    const bool sites_on_device = site_copy != nullptr;
    Context& ctx = *context_;
    const std::size_t n = std::size_t(input.sites.size());
    const double per_bucket = input.layout.sites_per_bucket > 0 ? input.layout.sites_per_bucket : 2.0;
    const bool cpu_device = this->cpu_device();
    const bool in_place = works_in_place();

    auto start = Clock::now();
    const StarCells frame = plan_star_cells(site_copy ? site_copy->sample() : star_cell_sample(input.sites), n,
                                            input.sites.bounds, per_bucket, ctx.max_buffer_bytes());
    const int cells = frame.cells;
    const std::size_t cell_entries = std::size_t(cells) * std::size_t(cells) + 1;
    result.host_stages.push_back({frame.quantile ? "vulkan: grid (quantile cells)" : "vulkan: grid", ms_since(start)});

    // Each triangle is emitted once and there are at most 2n - 5.
    const std::size_t capacity = 2 * n;
    // Slots whose adjacency the device cannot find (both far vertices deferred); more than this
    // and the adjacency is left to the host.
    const std::size_t unresolved_capacity = n / 4 + 1024;
    ctx.require_fits(bytes_of(n, 16), "the sites");
    ctx.require_fits(bytes_of(cell_entries, 4), "the grid");
    ctx.require_fits(bytes_of(capacity, 12), "the triangle output");
    ctx.require_fits(bytes_of(n, 4 * star_capacity), "the stars");
    if (std::max<std::size_t>(n, cell_entries) > ctx.limits().maxTexelBufferElements)
      throw Error(ErrorCode::too_large,
                  "Vulkan: " + std::to_string(std::max<std::size_t>(n, cell_entries)) +
                      " texels in one texel buffer; device " + ctx.name() + " allows " +
                      std::to_string(ctx.limits().maxTexelBufferElements));

    // On lavapipe one workgroup = one SIMD batch, so the loop cap (see loop_budget) is shared
    // by as few invocations as possible.
    const std::uint32_t wg =
        workgroup(star_workgroup_override() ? star_workgroup_override()
                  : cpu_device              ? std::max(1u, ctx.physical().subgroup_size)
                                            : 64u);

    const bool device_bucketing = bucket_on_device(cpu_device);
    // Its kernels are compiled on first use only: CPU devices bucket on the host.
    std::optional<DeviceBucketing> bucketing;
    if (device_bucketing) bucketing.emplace(ctx, wg, frame.quantile);
    start = Clock::now();
    // The star kernel's inputs: host-visible where the host buckets in place.
    Buffer& sites = kept(k_sites, bytes_of(n, 16), in_place);
    Buffer& cell_start = kept(k_cell_start, bytes_of(cell_entries, 4), in_place);
    Buffer& predecessor = kept(k_predecessor, bytes_of(n, 4), in_place);
    // Read by the host: in place on a CPU device, else downloaded.
    Buffer& triangles = kept(k_triangles, bytes_of(capacity, 12), in_place);
    Buffer& counters = kept(k_counters, 64, in_place);
    Buffer& stars = kept(k_stars, bytes_of(n, 4 * star_capacity), in_place);
    Buffer& site_info = kept(k_site_info, bytes_of(n, 8), in_place);
    // Quantile cells' boundaries (a placeholder with uniform cells): written now, before the
    // first submission reads them.
    Buffer& cell_bounds = kept(k_cell_bounds, std::max<VkDeviceSize>(16, bytes_of(frame.bounds.size(), 8)), in_place);
    if (!frame.bounds.empty()) {
      if (in_place) {
        std::memcpy(cell_bounds.mapped(), frame.bounds.data(), bytes_of(frame.bounds.size(), 8));
      } else {
        const StagingRing::Upload bounds[] = {{frame.bounds.data(), cell_bounds.handle(), 0, bytes_of(frame.bounds.size(), 8)}};
        ctx.staging().upload(bounds);
      }
    }
    Buffer *neighbors = nullptr, *unresolved = nullptr, *words = nullptr;
    // Device bucketing: the inputs in SiteSet order, written by the host (in place on a CPU
    // device, else staged), and buffers the device alone makes and reads.
    Buffer *input_sites = nullptr, *input_predecessor = nullptr, *to_site = nullptr;
    if (device_bucketing) {
      input_sites = &kept(k_input_sites, bytes_of(n, 16), in_place);
      input_predecessor = &kept(k_input_predecessor, bytes_of(n, 4), in_place);
      to_site = &kept(k_to_site, bytes_of(n, 4), false);
      bucketing->bind({input_sites, input_predecessor, &kept(k_cell_key, bytes_of(n, 4), false),
                      &cell_start, &kept(k_cursor, bytes_of(cell_entries - 1, 4), false),
                      &kept(k_unordered, bytes_of(n, 4), false), &sites, to_site,
                      &kept(k_to_sorted, bytes_of(n, 4), false), &predecessor, &triangles,
                      &counters,
                      &kept(k_scan_sums, bucketing->scan_sums_bytes(cell_entries), false), &cell_bounds});
    }
    // The device audits the adjacency where it has the triangles in SiteSet ids and the hull
    // (device bucketing), and made the adjacency (GPU path): open slots, as many as unresolved.
    const bool device_audit = device_bucketing && !in_place;
    Buffer* open_slots = nullptr;
    if (!in_place) {
      neighbors = &kept(k_neighbors, bytes_of(capacity, 12), false);
      unresolved = &kept(k_unresolved, bytes_of(unresolved_capacity, 4), false);
      if (device_audit) open_slots = &kept(k_open_slots, bytes_of(unresolved_capacity, 4), false);
      // The counters come back here at the end of each submission (the rest by the ring).
      words = &kept(k_words, 64, true);
    }
    result.host_stages.push_back({"vulkan: allocate", ms_since(start)});
    // Whatever happens below, the cache keeps at most keep_bytes() once this call is over.
    struct Trim {
      Context& ctx;
      ~Trim() {
        try {
          ctx.buffers().trim(ctx.keep_bytes());
        } catch (...) {  // a failed wait: the buffers stay, the call's own error goes on
        }
      }
    } trim{ctx};

    // First submission: the sites into cells. Its one question for the host (was a cell too
    // crowded to rank on the device?) is asked before the star kernel runs.
    bool device_sorted = false;
    if (device_bucketing) {
      start = Clock::now();
      if (sites_on_device) {
        // prepare_on_device left them there.
      } else if (in_place) {
        copy_on_host_threads(input_sites->mapped(), input.sites.points.data(), bytes_of(n, 16));
        copy_on_host_threads(input_predecessor->mapped(), input.hull.predecessor.data(),
                             bytes_of(n, 4));
      } else {
        // Chunk by chunk through the ring: the host's copy of one chunk overlaps the transfer
        // of the previous one.
        const StagingRing::Upload pieces[] = {
            {input.sites.points.data(), input_sites->handle(), 0, bytes_of(n, 16)},
            {input.hull.predecessor.data(), input_predecessor->handle(), 0, bytes_of(n, 4)}};
        ctx.staging().upload(pieces);
      }
      if (!sites_on_device) result.host_stages.push_back({"vulkan: stage", ms_since(start)});

      start = Clock::now();
      Recording rec(ctx);
      rec.barrier();  // after the ring's copies
      GridShape shape{{frame.origin[0], frame.origin[1]}, {frame.inv_width[0], frame.inv_width[1]}, cells};
      bucketing->record_sort(rec, shape, n);
      rec.timestamp("vulkan: bucket");
      if (!in_place) rec.copy(counters, *words, counters.size());
      rec.barrier_to_host();  // the counters (in place: all the host reads)
      for (StageTime& stage : rec.submit()) result.device_stages.push_back(std::move(stage));
      result.host_stages.push_back({"vulkan: bucket (submit + wait)", ms_since(start)});
      const auto* at = static_cast<const std::uint32_t*>(in_place ? counters.mapped() : words->mapped());
      device_sorted = at[crowded_cell_counter] == 0;
    }

    // One class, or the GPU path: a light first pass (each class's) and a retry of the sites it
    // hands on (star.comp's EXACT_PATH and RETRY); classes in place: every pass with the exact
    // path. Integer inputs that are no small lattice take the full pass too: the filters leave
    // the cocircular cells of nearly every site undecided, and the light pass would hand nearly
    // all of them on (a 120 x 120 grid 100 units apart hands on every site).
    const std::uint64_t classes = star_passes();
    const bool one_or_gpu = classes == 1 || !in_place;
    const bool lattice = exact_lattice_arithmetic(input.sites) && exact_lattice_search();
    const bool light = one_or_gpu && light_first_pass() && (lattice || !input.sites.integer_coordinates);
    // The retry dispatch also decides incircles from exact coordinate differences (star.comp's
    // EXACT_DIFFERENCES).
    auto star_spec = [&](bool exact_path, bool retry, std::uint32_t edge_part) {
      return std::array<std::uint32_t, 10>{wg, star_capacity, loop_budget(true), apex_filters(),
                                           lattice ? 1u : 0u, frame.quantile ? 1u : 0u, exact_path ? 1u : 0u,
                                           retry ? 1u : 0u, retry ? 1u : 0u, edge_part};
    };
    const VkDescriptorType texel = VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER,
                           storage = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    const VkDescriptorType star_types[] = {texel, texel, texel, storage, storage, storage, storage, storage};
    TexelView site_view(ctx, sites, VK_FORMAT_R32G32B32A32_UINT, bytes_of(n, 16));
    TexelView cell_view(ctx, cell_start, VK_FORMAT_R32_SINT, bytes_of(cell_entries, 4));
    TexelView predecessor_view(ctx, predecessor, VK_FORMAT_R32_SINT, bytes_of(n, 4));
    Buffer* bindings[] = {&sites, &cell_start, &predecessor, &triangles, &counters, &stars, &site_info, &cell_bounds};
    const TexelView* texels[] = {&site_view, &cell_view, &predecessor_view, nullptr, nullptr, nullptr, nullptr, nullptr};
    auto star_kernel = [&](bool exact_path, bool retry, std::uint32_t edge_part = 0) -> Kernel& {
      const auto spec = star_spec(exact_path, retry, edge_part);
      Kernel& k = ctx.kernel("star", spirv::star(), 8, sizeof(StarParams), spec, star_types);
      k.bind(bindings, texels);
      return k;
    };
    // One class or the GPU path, on a device of our own: each class's sites of the grid's outer
    // ring first, then the rest with no barrier between (star.comp's EDGE_PART).
    // EXPANSE_VULKAN_EDGE=0 walks every site of a class in one dispatch. Not on a lent device:
    // its queue may carry the application's synchronisation validation, which counts two
    // dispatches writing one buffer as a hazard even where their sites differ.
    const bool edge_apart = one_or_gpu && !ctx.borrowed() && edge_first();
    std::vector<Kernel*> first_kernels;
    if (edge_apart)
      first_kernels = {&star_kernel(!light, false, 1), &star_kernel(!light, false, 2)};
    else
      first_kernels = {&star_kernel(!light, false)};
    Kernel* retry_kernel = light ? &star_kernel(true, true) : nullptr;
    Kernel* links = nullptr;
    if (!in_place) {
      const std::uint32_t link_spec[] = {wg, star_capacity};
      links = &ctx.kernel("star_links", spirv::star_links(), 5, sizeof(LinkParams), link_spec);
      Buffer* link_bindings[] = {&stars, &site_info, neighbors, unresolved, &counters};
      links->bind(link_bindings);
    }

    start = Clock::now();
    StarGrid host_grid;  // when the host bucketed: its sorted id -> SiteSet id
    if (!device_sorted) {
      if (site_copy) {  // the host's bucketing reads the sites
        site_copy->start();
        site_copy->finish();
      }
      bucket_on_host(input, frame, sites, cell_start, predecessor, host_grid);
      result.host_stages.push_back({"vulkan: bucket", ms_since(start)});
      start = Clock::now();
    }
    // The sites' copy to the host runs beside the stars: submitted after every ring upload
    // (whose barriers would wait for it) and after the bucketing's submission (whose fence
    // would), and the star submission waits for earlier compute work only.
    if (site_copy) site_copy->start();
    Recording rec(ctx);
    if (device_sorted)
      rec.barrier_after_compute();  // no ring copies since the bucketing's submission
    else
      rec.barrier();  // after the ring's copies
    rec.fill(counters, 0);
    if (classes > 1) rec.fill(site_info, ~0u);  // no earlier neighbours listed yet (star.comp)
    rec.barrier();
    // A scan of more than ~48 sites' worth of cells (at the typical site's density) re-plans
    // on finding a better candidate.
    StarParams params{{{frame.origin[0], frame.origin[1]}, {frame.inv_width[0], frame.inv_width[1]},
                       cells, std::int32_t(n), 0, std::int32_t(capacity)},
                      std::int32_t(std::clamp(48.0 / per_bucket, 4.0, 1.0e6)),
                      0,
                      0,
                      0};
    const std::uint64_t max_groups = ctx.limits().maxComputeWorkGroupCount[0];
    params.pass_mask = std::int32_t(classes - 1);
    params.pass_shift = classes > 1 ? std::int32_t(star_class_shift()) : 0;
    const std::uint64_t runs = (n + (std::uint64_t{1} << params.pass_shift) - 1) >> params.pass_shift;
    for (std::uint64_t pass = 0; pass < classes && pass < runs; ++pass) {
      params.pass = std::int32_t(pass);
      const std::uint64_t count = ((runs - pass + classes - 1) / classes) << params.pass_shift;
      for (Kernel* kernel : first_kernels) {
        for (std::uint64_t first = 0; first < count; first += max_groups * wg) {
          params.grid.first = std::int32_t(first);
          const std::uint64_t left = (count - first + wg - 1) / wg;
          rec.dispatch(*kernel, &params, std::uint32_t(std::min(left, max_groups)));
        }
      }
      rec.barrier();
    }
    if (retry_kernel) {  // the sites the light pass handed on (a site that was not exits at once)
      params.pass = params.pass_mask = params.pass_shift = 0;  // every site, none reading or posting
      for (std::uint64_t first = 0; first < n; first += max_groups * wg) {
        params.grid.first = std::int32_t(first);
        const std::uint64_t left = (n - first + wg - 1) / wg;
        rec.dispatch(*retry_kernel, &params, std::uint32_t(std::min(left, max_groups)));
      }
      rec.barrier();
    }
    rec.timestamp("vulkan: stars");
    if (links) {
      LinkParams link_params{std::int32_t(n), 0, std::int32_t(unresolved_capacity), 0};
      for (std::uint64_t first = 0; first < n; first += max_groups * wg) {
        link_params.first = std::int32_t(first);
        const std::uint64_t left = (n - first + wg - 1) / wg;
        rec.dispatch(*links, &link_params, std::uint32_t(std::min(left, max_groups)));
      }
      rec.barrier();
      rec.timestamp("vulkan: links");
    }
    // The triangles are in sorted ids; whoever bucketed maps them back to SiteSet ids.
    if (device_sorted) {
      bucketing->record_restore(rec, n, capacity);
      rec.timestamp("vulkan: restore ids");
    }
    if (device_sorted && device_audit) {
      record_audit(ctx, rec, wg, triangles, *neighbors, *input_predecessor, *open_slots, counters,
                   capacity, unresolved_capacity);
      rec.timestamp("vulkan: audit");
    }
    // Only the counters here: the host reads them, then downloads what was made (not the
    // capacity) through the ring. In place, the host reads the buffers themselves.
    if (!in_place) rec.copy(counters, *words, counters.size());
    rec.barrier_to_host();
    // While the device works, the host readies the output vectors (faulting in 805 MB at
    // 4096^2 took the H100's host ~220 ms in the CUDA backend, overlapped with its kernel).
    auto& partial = result.partial;
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
      allocate_full_triangulation(partial, n, input.hull.sites.size(), input.recycled);
    } catch (...) {
      waiter.join();
      throw;
    }
    const auto host_done = Clock::now();
    waiter.join();
    if (device_failure) std::rethrow_exception(device_failure);
    for (StageTime& stage : device_stages) result.device_stages.push_back(std::move(stage));
    result.host_stages.push_back({"vulkan: submit + wait", ms_since(start)});
    // What the wait above was made of: the device's work (submission to fence, host clock)
    // and the output vectors' allocation beside it; the longer of the two is the wait.
    result.host_stages.push_back(
        {"vulkan: device work (host clock)", std::chrono::duration<double, std::milli>(device_done - host_start).count()});
    result.host_stages.push_back(
        {"vulkan: output allocation (host, while the device works)",
         std::chrono::duration<double, std::milli>(host_done - host_start).count()});

    start = Clock::now();
    std::uint32_t count[16];
    std::memcpy(count, in_place ? counters.mapped() : words->mapped(), sizeof(count));
    if (count[2] != 0 || count[0] > capacity || count[0] > partial.triangles.size())
      throw Error(ErrorCode::internal, "Vulkan: star output overflowed its capacity");
    if (count[invalid_site_id_counter] != 0)
      throw Error(ErrorCode::internal, "Vulkan: the device returned an invalid site id");
    static_assert(sizeof(partial.triangles[0]) == 12 && sizeof(partial.neighbors[0]) == 12);
    // The GPU path's adjacency: count[5], the links pass hit lavapipe's loop cap; count[6], too
    // many unresolved slots. Either way it is left empty (its room kept), and the pipeline
    // derives it.
    const bool device_links = !in_place && count[5] == 0 && count[6] == 0;
    std::vector<std::int32_t> unresolved_slots, open_list;
    const bool check_open = device_links && device_sorted && device_audit &&
                            count[open_overflow_counter] == 0;
    if (!in_place) {
      // Everything the host reads, in one pass through the ring: the triangles (straight into
      // the output vector), the adjacency, and the short lists.
      std::vector<StagingRing::Download> pieces{
          {triangles.handle(), 0, partial.triangles.data(), bytes_of(count[0], 12)}};
      if (device_links) {
        unresolved_slots.resize(std::min<std::size_t>(count[4], unresolved_capacity));
        pieces.push_back({neighbors->handle(), 0, partial.neighbors.data(), bytes_of(count[0], 12)});
        pieces.push_back({unresolved->handle(), 0, unresolved_slots.data(), bytes_of(unresolved_slots.size(), 4)});
      }
      if (check_open) {
        open_list.resize(std::min<std::size_t>(count[open_edge_counter], unresolved_capacity));
        pieces.push_back({open_slots->handle(), 0, open_list.data(), bytes_of(open_list.size(), 4)});
      }
      ctx.staging().download(pieces);
    }
    if (in_place && device_sorted)
      copy_on_host_threads(partial.triangles.data(), triangles.mapped(), bytes_of(count[0], 12));
    else if (!device_sorted)
      // The triangles in sorted ids (downloaded into the output, or in place) to SiteSet ids;
      // each id is read before its slot is written, so the two may be the same memory.
      restore_on_host(host_grid,
                      static_cast<const std::int32_t*>(in_place ? triangles.mapped()
                                                                : static_cast<void*>(partial.triangles.data())),
                      count[0], partial);
    partial.triangles.resize(count[0]);
    partial.deferred_expansions = count[1];
    result.iterations = 1;
    result.host_stages.push_back({"vulkan: read back", ms_since(start)});

    start = Clock::now();
    if (in_place) {
      link_stars(static_cast<const std::int32_t*>(stars.mapped()),
                 static_cast<const std::int32_t*>(site_info.mapped()), n, partial);
      result.host_stages.push_back({"vulkan: links (host)", ms_since(start)});
    } else if (device_links) {
      partial.neighbors.resize(count[0]);
      if (unresolved_slots.size() < count[4])
        throw Error(ErrorCode::internal, "Vulkan: more unresolved slots than their capacity");
      pair_unresolved(unresolved_slots, partial);
      result.host_stages.push_back({"vulkan: links (read back)", ms_since(start)});
      if (check_open) {
        // A failed device audit is final: the pipeline derives the adjacency itself (the host
        // audit would find the same, after reading all of it).
        start = Clock::now();
        result.adjacency_audited =
            count[bad_link_counter] == 0 && open_list.size() == count[open_edge_counter] &&
            open_edges_check_out(open_list, unresolved_slots, partial);
        if (!result.adjacency_audited) partial.neighbors.clear();
        result.host_stages.push_back({"vulkan: audit (open edges)", ms_since(start)});
      }
    } else {
      partial.neighbors.clear();
    }
  }

  // A star as the host reads it, in place (star_common.glsl's layout).
  struct HostStar {
    const std::int32_t* row = nullptr;
    std::int32_t site = -1;
    std::uint32_t info = 0;
    std::int32_t base = -1;
    int degree = 0, start = 0;
    bool closed() const { return (info & (1u << 9)) != 0; }
    bool deferred() const { return (info & (1u << 10)) != 0; }
    bool emitted() const { return !deferred() && base >= 0; }  // owns output triangles
    int triangles() const { return closed() ? degree : degree - 1; }
    std::uint32_t owned() const { return info >> 16; }
    bool owns(int t) const { return ((owned() >> t) & 1u) != 0; }
    std::int32_t output(int t) const {
      std::uint32_t below = owned() & ((1u << t) - 1u);
      below = below - ((below >> 1) & 0x5555u);  // 16-bit popcount without a library call
      below = (below & 0x3333u) + ((below >> 2) & 0x3333u);
      below = (below + (below >> 4)) & 0x0f0fu;
      return base + std::int32_t((below + (below >> 8)) & 0x1fu);
    }
    std::int32_t at(int t) const {
      t = t < 0 ? t + degree : (t >= degree ? t - degree : t);
      return row[(start + t) & 15];
    }
    // u's position in the star, or -1. The row's 16 slots compared at once, then
    // only the star's slots kept (degree of them from `start`, wrapping); a site is in a star
    // at most once. 1M uniform sites on lavapipe: links 68 -> 55-57 ms against a loop over the
    // star's entries.
    int find(std::int32_t u) const {
      std::uint32_t matches = 0;
#if defined(__SSE2__)
      // GCC leaves the loop below scalar (a compare and a set per slot): lavapipe, 1M uniform,
      // links 56-58 ms with it, 46.0-46.2 with these four compares (2026-11-25).
      const __m128i key = _mm_set1_epi32(u);
      for (int q = 0; q < 4; ++q) {
        const __m128i slots = _mm_loadu_si128(reinterpret_cast<const __m128i*>(row) + q);
        matches |= std::uint32_t(_mm_movemask_ps(_mm_castsi128_ps(_mm_cmpeq_epi32(slots, key)))) << (4 * q);
      }
#else
      for (int k = 0; k < 16; ++k) matches |= std::uint32_t(row[k] == u) << k;
#endif
      const std::uint32_t span = degree >= 16 ? 0xffffu : (1u << degree) - 1u;
      matches &= ((span << start) | (span >> (16 - start))) & 0xffffu;
      if (matches == 0) return -1;
      return (std::countr_zero(matches) - start) & 15;
    }
  };

  // The host twin of star_links.comp, over the stars in place: the same adjacency. A first pass
  // checks every star (ids in range, degree, output range), so that a faulty device cannot make
  // the host misbehave; the second reads them unchecked.
  static void link_stars(const std::int32_t* star, const std::int32_t* info_base, std::size_t n,
                         PartialTriangulation& partial) {
    const std::size_t count = partial.triangles.size();
    auto& nbrs = partial.neighbors;
    nbrs.assign(count, {no_neighbor, no_neighbor, no_neighbor});
    auto star_of = [&](std::int32_t s) {
      HostStar h;
      h.site = s;
      h.row = star + 16 * std::size_t(s);
      h.info = std::uint32_t(info_base[2 * std::size_t(s)]);
      h.base = info_base[2 * std::size_t(s) + 1];
      h.degree = int(h.info & 31u);
      h.start = int((h.info >> 5) & 15u);
      return h;
    };
    const unsigned workers = host_workers(n);
    std::atomic<bool> bad{false};
    parallel_chunks(n, workers, [&](std::size_t begin, std::size_t end, unsigned) {
      for (std::size_t s = begin; s < end; ++s) {
        const HostStar h = star_of(std::int32_t(s));
        if (h.deferred()) continue;
        bool ok = h.degree >= 1 && h.degree <= 16 &&
                  (h.base < 0 || std::size_t(h.output(16)) <= count);
        for (int t = 0; t < h.degree; ++t) ok = ok && h.at(t) >= 0 && std::size_t(h.at(t)) < n;
        if (!ok) bad = true;
      }
    });
    if (bad) throw Error(ErrorCode::internal, "Vulkan: the device returned an invalid star");
    // Output index of triangle (o, u, w) in the star of its owner o, or no_neighbor.
    auto index_in = [&](const HostStar& o, std::int32_t u, std::int32_t w) -> std::int32_t {
      if (!o.emitted()) return no_neighbor;
      const int t = o.find(u);
      if (t < 0 || t >= o.triangles() || o.at(t + 1) != w || !o.owns(t)) return no_neighbor;
      return o.output(t);
    };
    // Output index of the counter-clockwise triangle (x, y, z); `own` is a star already read.
    auto index = [&](const HostStar& own, std::int32_t x, std::int32_t y, std::int32_t z) {
      std::int32_t o = x, u = y, w = z;
      if (y < o && y < z) {
        o = y, u = z, w = x;
      } else if (z < o && z < y) {
        o = z, u = x, w = y;
      }
      return index_in(o == own.site ? own : star_of(o), u, w);
    };
    // The same, for the triangle at position k of a star already read whose site owns it (the
    // find that index() would make is the one this position came from): lavapipe, 1M uniform,
    // links 46 -> 41.5 ms.
    auto owned_at = [](const HostStar& o, int k) -> std::int32_t {
      k = k < 0 ? k + o.degree : (k >= o.degree ? k - o.degree : k);
      return o.emitted() && o.owns(k) ? o.output(k) : no_neighbor;
    };
    std::vector<std::vector<std::int32_t>> open(workers);
    parallel_chunks(n, workers, [&](std::size_t begin, std::size_t end, unsigned w) {
      for (std::size_t si = begin; si < end; ++si) {
        const HostStar me = star_of(std::int32_t(si));
        if (!me.emitted()) continue;
        const std::int32_t s = me.site;
        for (std::uint32_t left = me.owned(); left != 0; left &= left - 1) {
          const int t = std::countr_zero(left);
          if (t >= me.triangles()) break;  // never, for a valid star
          const std::int32_t a = me.at(t), b = me.at(t + 1);
          const std::int32_t out = me.output(t);
          auto& row = nbrs[std::size_t(out)];
          // Opposite s: (b, a, r), r the neighbour of a before b (or of b after a).
          const HostStar sa = star_of(a), sb = star_of(b);
          if (!sa.deferred()) {
            const int p = sa.find(b);
            if (p >= 0 && (p > 0 || sa.closed())) {
              const std::int32_t r = sa.at(p - 1);
              row[0] = a < b && a < r ? owned_at(sa, p - 1) : index(sa, b, a, r);
            }
          } else if (!sb.deferred()) {
            const int q = sb.find(a);
            if (q >= 0 && (q < sb.degree - 1 || sb.closed())) row[0] = index(sb, b, a, sb.at(q + 1));
          } else {
            open[w].push_back(3 * out);
          }
          // Opposite a: (s, b, next), s's next triangle; opposite b: (s, previous, a).
          if (me.closed() || t + 2 < me.degree) {
            const std::int32_t next = me.at(t + 2);
            row[1] = s < next ? owned_at(me, t + 1) : index(me, s, b, next);  // s < b: s owns t
          }
          if (me.closed() || t >= 1) {
            const std::int32_t previous = me.at(t - 1);
            row[2] = s < previous ? owned_at(me, t - 1) : index(me, s, previous, a);  // s < a
          }
        }
      }
    });
    std::vector<std::int32_t> slots;
    for (const auto& list : open) slots.insert(slots.end(), list.begin(), list.end());
    pair_unresolved(slots, partial);
  }

  // Links the slots listed as unresolved (edges whose two vertices both deferred): the triangle
  // across x->y, if emitted, is listed too with y->x, so pairing the listed slots by edge
  // completes the adjacency.
  static void pair_unresolved(const std::vector<std::int32_t>& slots, PartialTriangulation& partial) {
    if (slots.empty()) return;
    const std::size_t count = partial.triangles.size();
    auto& nbrs = partial.neighbors;
    auto edge = [&](std::int32_t slot, bool reversed) {
      const Triangle& t = partial.triangles[std::size_t(slot / 3)];
      const int k = slot % 3;
      std::uint64_t x = std::uint32_t(t[std::size_t((k + 1) % 3)]);
      std::uint64_t y = std::uint32_t(t[std::size_t((k + 2) % 3)]);
      if (reversed) std::swap(x, y);
      return (x << 32) | y;
    };
    std::unordered_map<std::uint64_t, std::int32_t> open;
    open.reserve(slots.size());
    for (std::int32_t slot : slots) {
      if (slot < 0 || std::size_t(slot / 3) >= count)
        throw Error(ErrorCode::internal, "Vulkan: the device listed an invalid adjacency slot");
      open.emplace(edge(slot, false), slot);
    }
    for (std::int32_t slot : slots) {
      const auto found = open.find(edge(slot, true));
      nbrs[std::size_t(slot / 3)][std::size_t(slot % 3)] =
          found == open.end() ? no_neighbor : found->second / 3;
    }
  }

  void grow_blocks(const GrowInput& input, GrowResult& result) {
    Context& ctx = *context_;
    const Layout& layout = input.layout;
    const std::size_t n = std::size_t(input.sites.size());
    if (layout.blocks_per_side < 1 || layout.buckets_per_block_side < 1 ||
        layout.blocks_per_side > 4096 || layout.buckets_per_block_side > 4096 ||
        !(layout.halo_fraction >= 0.0 && layout.halo_fraction <= 1.0) ||
        layout.threads_per_block < 0)
      throw Error(ErrorCode::invalid_argument,
                  "paper layout: blocks and buckets per side must be in [1, 4096], halo in [0, 1]");
    const int B = layout.blocks_per_side, K = layout.buckets_per_block_side;
    const long long cells_ll = (long long)B * K;
    if (cells_ll > 16384)
      throw Error(ErrorCode::invalid_argument, "paper layout: blocks x buckets per side > 16384");
    const int cells = int(cells_ll);
    const int halo = int(std::ceil(layout.halo_fraction * K));

    auto start = Clock::now();
    Sorted s = bucket(input, cells);
    const int blocks = B * B;
    // Owner block of each site, local lists (ext cell range, local cell order).
    std::vector<std::int32_t> owner(n);
    for (std::size_t k = 0; k < n; ++k) {
      const int cx = s.cell_of[k] % cells, cy = s.cell_of[k] / cells;
      owner[k] = (cy / K) * B + (cx / K);
    }
    std::vector<std::int32_t> info(std::size_t(blocks) * 12);
    std::vector<std::int32_t> local_ids, local_cells;
    std::size_t hash_total = 0, active_total = 0;
    for (int bj = 0; bj < B; ++bj) {
      for (int bi = 0; bi < B; ++bi) {
        const int b = bj * B + bi;
        const int lox = std::max(0, bi * K - halo), hix = std::min(cells - 1, bi * K + K - 1 + halo);
        const int loy = std::max(0, bj * K - halo), hiy = std::min(cells - 1, bj * K + K - 1 + halo);
        std::int32_t* in = &info[std::size_t(b) * 12];
        in[0] = lox;
        in[1] = loy;
        in[2] = hix;
        in[3] = hiy;
        in[4] = std::int32_t(local_cells.size());
        const std::size_t slot_base = local_ids.size();
        in[5] = std::int32_t(slot_base);
        // Seed: own site nearest the block centre (any choice is correct; this one is the paper's).
        const double cx = s.origin[0] + (bi * K + K * 0.5) / s.inv_width[0];
        const double cy = s.origin[1] + (bj * K + K * 0.5) / s.inv_width[1];
        double best = INFINITY;
        int seed = -1;
        for (int y = loy; y <= hiy; ++y) {
          for (int x = lox; x <= hix; ++x) {
            local_cells.push_back(std::int32_t(local_ids.size()));
            const int c = y * cells + x;
            for (int k = s.cell_start[std::size_t(c)]; k < s.cell_start[std::size_t(c) + 1]; ++k) {
              if (owner[std::size_t(k)] == b) {
                const double dx = s.points[std::size_t(k)].x - cx, dy = s.points[std::size_t(k)].y - cy;
                if (dx * dx + dy * dy < best) {
                  best = dx * dx + dy * dy;
                  seed = int(local_ids.size() - slot_base);
                }
              }
              local_ids.push_back(k);
            }
          }
        }
        local_cells.push_back(std::int32_t(local_ids.size()));
        const std::size_t count = local_ids.size() - slot_base;
        if (count > 65535)
          throw Error(ErrorCode::too_large,
                      "paper layout: a block holds " + std::to_string(count) +
                          " sites with its halo (at most 65535); use more blocks");
        if (local_ids.size() > std::size_t(INT32_MAX) / 2)
          throw Error(ErrorCode::too_large, "paper layout: too many block-local sites");
        in[6] = std::int32_t(count);
        in[7] = count >= 2 ? seed : -1;
        const std::size_t hash_cap = 8 * count + 64, active_cap = 3 * count + 64;
        in[8] = std::int32_t(hash_total);
        in[9] = std::int32_t(hash_cap);
        in[10] = std::int32_t(active_total);
        in[11] = std::int32_t(active_cap);
        hash_total += hash_cap;
        active_total += 2 * active_cap;
      }
    }
    result.host_stages.push_back({"vulkan: bucket + blocks", ms_since(start)});

    const std::size_t capacity = 2 * n;
    ctx.require_fits(bytes_of(n, 16), "the sites");
    ctx.require_fits(bytes_of(local_ids.size(), 4), "the block-local site lists");
    ctx.require_fits(bytes_of(hash_total, 4), "the blocks' edge sets");
    ctx.require_fits(bytes_of(active_total, 4), "the blocks' active edge lists");
    ctx.require_fits(bytes_of(capacity, 12), "the triangle output");

    start = Clock::now();
    Buffer sites(ctx, bytes_of(n, 16), false);
    Buffer ids(ctx, bytes_of(local_ids.size(), 4), false);
    Buffer cell_start(ctx, bytes_of(local_cells.size(), 4), false);
    Buffer predecessor(ctx, bytes_of(n, 4), false);
    Buffer owners(ctx, bytes_of(n, 4), false);
    Buffer block_info(ctx, bytes_of(info.size(), 4), false);
    Buffer edge_set(ctx, bytes_of(hash_total, 4), false);
    Buffer active(ctx, bytes_of(active_total, 4), false);
    Buffer triangles(ctx, bytes_of(capacity, 12), false);
    Buffer counters(ctx, 64, false);
    Buffer words(ctx, 64, true);
    // Through the context's staging ring, chunk by chunk (the kernel's recording starts with a
    // barrier after these copies).
    const StagingRing::Upload pieces[] = {
        {s.points.data(), sites.handle(), 0, bytes_of(n, 16)},
        {local_ids.data(), ids.handle(), 0, bytes_of(local_ids.size(), 4)},
        {local_cells.data(), cell_start.handle(), 0, bytes_of(local_cells.size(), 4)},
        {s.predecessor.data(), predecessor.handle(), 0, bytes_of(n, 4)},
        {owner.data(), owners.handle(), 0, bytes_of(n, 4)},
        {info.data(), block_info.handle(), 0, bytes_of(info.size(), 4)}};
    ctx.staging().upload(pieces);
    // The buffers above outlive no copy in flight, even when this call throws.
    struct Idle {
      Context& ctx;
      ~Idle() {
        try {
          ctx.wait_staging();
        } catch (...) {
        }
      }
    } idle{ctx};
    result.host_stages.push_back({"vulkan: allocate + stage", ms_since(start)});

    std::uint32_t threads = std::uint32_t(layout.threads_per_block);
    if (threads == 0)
      threads = std::uint32_t(std::clamp(std::sqrt(double(n) / blocks), 32.0, 1024.0));
    threads = workgroup(threads);
    const std::uint32_t spec[] = {threads, loop_budget(false)};
    Kernel& kernel = ctx.kernel("blocks", spirv::blocks(), 10, sizeof(GridParams), spec);
    Buffer* bindings[] = {&sites, &ids, &cell_start, &predecessor, &owners,
                          &block_info, &edge_set, &active, &triangles, &counters};
    kernel.bind(bindings);

    start = Clock::now();
    Recording rec(ctx);
    rec.barrier();  // after the ring's copies
    rec.fill(edge_set, 0xffffffffu);
    rec.fill(counters, 0);
    rec.barrier();
    rec.timestamp("vulkan: upload");
    GridParams params{{s.origin[0], s.origin[1]}, {s.inv_width[0], s.inv_width[1]}, cells,
                      blocks, 0, std::int32_t(capacity)};
    const std::uint64_t max_groups = ctx.limits().maxComputeWorkGroupCount[0];
    for (std::uint64_t first = 0; first < std::uint64_t(blocks); first += max_groups) {
      params.first = std::int32_t(first);
      rec.dispatch(kernel, &params, std::uint32_t(std::min<std::uint64_t>(blocks - first, max_groups)));
    }
    rec.barrier();
    rec.timestamp("vulkan: blocks");
    rec.copy(counters, words, counters.size());
    rec.barrier_to_host();
    result.device_stages = rec.submit();
    result.host_stages.push_back({"vulkan: submit + wait", ms_since(start)});

    start = Clock::now();
    std::uint32_t count[16];
    std::memcpy(count, words.mapped(), sizeof(count));
    if (count[2] != 0 || count[0] > capacity)
      throw Error(ErrorCode::internal, "Vulkan: block output overflowed its capacity");
    std::vector<std::int32_t> raw(std::size_t(count[0]) * 3);
    const StagingRing::Download made[] = {{triangles.handle(), 0, raw.data(), bytes_of(raw.size(), 4)}};
    ctx.staging().download(made);
    reserve_full_triangulation(result.partial, n, input.hull.sites.size());
    finish(s, raw, count[0], result);
    result.partial.deferred_expansions = count[1];
    result.iterations = count[3];
    result.host_stages.push_back({"vulkan: read back", ms_since(start)});
  }

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

void run_predicate_kernel(Context& ctx, std::span<const double> cases,
                          std::vector<std::int32_t>& signs, std::vector<double>& eft) {
  std::lock_guard lock(ctx.mutex());
  const std::size_t count = cases.size() / 8;
  signs.assign(count * kPredicateSigns, 0);
  eft.assign(count * 4, 0.0);
  if (count == 0) return;
  Buffer in(ctx, cases.size_bytes(), false);
  Buffer out_signs(ctx, bytes_of(count * kPredicateSigns, 4), false);
  Buffer out_eft(ctx, bytes_of(count * 4, 8), false);
  Buffer upload(ctx, cases.size_bytes(), true);
  Buffer download(ctx, out_signs.size() + out_eft.size(), true);
  std::memcpy(upload.mapped(), cases.data(), cases.size_bytes());
  const std::uint32_t wg = 64;
  const std::uint32_t spec[] = {wg};
  Kernel& kernel = ctx.kernel("predicate_test", spirv::predicate_test(), 3, 4, spec);
  Buffer* bindings[] = {&in, &out_signs, &out_eft};
  kernel.bind(bindings);
  Recording rec(ctx);
  rec.copy(upload, in, cases.size_bytes());
  rec.barrier();
  const std::int32_t n = std::int32_t(count);
  rec.dispatch(kernel, &n, std::uint32_t((count + wg - 1) / wg));
  rec.barrier();
  rec.copy(out_signs, download, out_signs.size(), 0, 0);
  rec.copy(out_eft, download, out_eft.size(), 0, out_signs.size());
  rec.barrier();
  rec.submit();
  std::memcpy(signs.data(), download.mapped(), signs.size() * 4);
  std::memcpy(eft.data(), static_cast<char*>(download.mapped()) + out_signs.size(),
              eft.size() * 8);
}

DeviceBuckets bucket_on_device(Context& ctx, const SiteSet& sites, const Hull& hull, int cells) {
  std::lock_guard lock(ctx.mutex());
  const std::size_t n = std::size_t(sites.size());
  const std::size_t cell_entries = std::size_t(cells) * std::size_t(cells) + 1;
  const std::uint32_t wg = 64;
  DeviceBucketing bucketing(ctx, wg, /*quantile_cells=*/false);
  Buffer input_sites(ctx, bytes_of(n, 16), false), input_predecessor(ctx, bytes_of(n, 4), false);
  Buffer cell_key(ctx, bytes_of(n, 4), false), cell_start(ctx, bytes_of(cell_entries, 4), false);
  Buffer cursor(ctx, bytes_of(cell_entries, 4), false), unordered(ctx, bytes_of(n, 4), false);
  Buffer sorted(ctx, bytes_of(n, 16), false), to_site(ctx, bytes_of(n, 4), false);
  Buffer to_sorted(ctx, bytes_of(n, 4), false), predecessor(ctx, bytes_of(n, 4), false);
  Buffer triangles(ctx, 16, false), counters(ctx, 64, false);
  Buffer scan_sums(ctx, bucketing.scan_sums_bytes(cell_entries), false), no_bounds(ctx, 16, false);
  bucketing.bind({&input_sites, &input_predecessor, &cell_key, &cell_start, &cursor, &unordered,
                  &sorted, &to_site, &to_sorted, &predecessor, &triangles, &counters, &scan_sums, &no_bounds});
  Buffer upload(ctx, bytes_of(n, 20), true);
  std::memcpy(upload.mapped(), sites.points.data(), bytes_of(n, 16));
  std::memcpy(static_cast<char*>(upload.mapped()) + bytes_of(n, 16), hull.predecessor.data(), bytes_of(n, 4));
  // Download layout: sorted sites, cell starts, to_site, predecessor, counters.
  const VkDeviceSize o_cells = bytes_of(n, 16), o_to_site = o_cells + bytes_of(cell_entries, 4),
                     o_pred = o_to_site + bytes_of(n, 4), o_counters = o_pred + bytes_of(n, 4);
  Buffer download(ctx, o_counters + 64, true);
  Recording rec(ctx);
  rec.copy(upload, input_sites, bytes_of(n, 16), 0);
  rec.copy(upload, input_predecessor, bytes_of(n, 4), bytes_of(n, 16));
  rec.barrier();
  const GridFrame frame(sites, cells);
  bucketing.record_sort(rec, {{frame.origin[0], frame.origin[1]}, {frame.inv_width[0], frame.inv_width[1]}, cells}, n);
  rec.copy(sorted, download, bytes_of(n, 16), 0, 0);
  rec.copy(cell_start, download, bytes_of(cell_entries, 4), 0, o_cells);
  rec.copy(to_site, download, bytes_of(n, 4), 0, o_to_site);
  rec.copy(predecessor, download, bytes_of(n, 4), 0, o_pred);
  rec.copy(counters, download, 64, 0, o_counters);
  rec.barrier();
  rec.submit();
  const char* out = static_cast<const char*>(download.mapped());
  DeviceBuckets b;
  b.sites.assign(reinterpret_cast<const Point2*>(out), reinterpret_cast<const Point2*>(out) + n);
  auto ints = [&](VkDeviceSize offset, std::size_t count) {
    const auto* p = reinterpret_cast<const std::int32_t*>(out + offset);
    return std::vector<std::int32_t>(p, p + count);
  };
  b.cell_start = ints(o_cells, cell_entries);
  b.to_site = ints(o_to_site, n);
  b.predecessor = ints(o_pred, n);
  b.crowded = reinterpret_cast<const std::uint32_t*>(out + o_counters)[crowded_cell_counter] != 0;
  return b;
}

bool audit_on_device(Context& ctx, const PartialTriangulation& partial, const Hull& hull) {
  std::lock_guard lock(ctx.mutex());
  const std::size_t count = partial.triangles.size();
  if (partial.neighbors.size() != count || count == 0) return false;
  const std::size_t sites = hull.predecessor.size(), open_capacity = count + 16;
  static_assert(sizeof(partial.triangles[0]) == 12 && sizeof(partial.neighbors[0]) == 12);
  Buffer triangles(ctx, bytes_of(count, 12), false), neighbors(ctx, bytes_of(count, 12), false);
  Buffer predecessor(ctx, bytes_of(sites, 4), false), open_slots(ctx, bytes_of(open_capacity, 4), false);
  Buffer counters(ctx, 64, false);
  const VkDeviceSize o_neighbors = bytes_of(count, 12), o_pred = 2 * o_neighbors,
                     o_counters = o_pred + bytes_of(sites, 4);
  Buffer upload(ctx, o_counters + 64, true);
  char* in = static_cast<char*>(upload.mapped());
  std::memcpy(in, partial.triangles.data(), bytes_of(count, 12));
  std::memcpy(in + o_neighbors, partial.neighbors.data(), bytes_of(count, 12));
  std::memcpy(in + o_pred, hull.predecessor.data(), bytes_of(sites, 4));
  std::uint32_t words[16] = {std::uint32_t(count)};
  std::memcpy(in + o_counters, words, sizeof(words));
  Buffer download(ctx, 64 + bytes_of(open_capacity, 4), true);
  Recording rec(ctx);
  rec.copy(upload, triangles, bytes_of(count, 12), 0);
  rec.copy(upload, neighbors, bytes_of(count, 12), o_neighbors);
  rec.copy(upload, predecessor, bytes_of(sites, 4), o_pred);
  rec.copy(upload, counters, 64, o_counters);
  rec.barrier();
  record_audit(ctx, rec, 64, triangles, neighbors, predecessor, open_slots, counters, count, open_capacity);
  rec.copy(counters, download, 64, 0, 0);
  rec.copy(open_slots, download, bytes_of(open_capacity, 4), 0, 64);
  rec.barrier();
  rec.submit();
  std::memcpy(words, download.mapped(), sizeof(words));
  if (words[bad_link_counter] != 0 || words[open_overflow_counter] != 0) return false;
  const auto* open = reinterpret_cast<const std::int32_t*>(static_cast<char*>(download.mapped()) + 64);
  return open_edges_check_out(std::vector<std::int32_t>(open, open + words[open_edge_counter]), {},
                              partial);
}

std::string eft_self_test(Context& ctx) {
  // a.x * a.y with a.x = a.y = 1 + 2^-30: exact 1 + 2^-29 + 2^-60; rounds to 1 + 2^-29, so
  // two_product's error must be exactly 2^-60, and a.x * a.y + b.x with b.x = -(1 + 2^-29) must
  // give 0 (an fma would give 2^-60). two_sum(1, 2^-60) must report error 2^-60.
  const double u = 1.0 + 0x1p-30;
  std::vector<double> cases = {u, u, -(1.0 + 0x1p-29), 0, 0, 1, 1, 1,
                               1.0, 0x1p-60, 0, 0, 0, 1, 1, 1};
  std::vector<std::int32_t> signs;
  std::vector<double> eft;
  run_predicate_kernel(ctx, cases, signs, eft);
  if (eft[1] != 1.0 + 0x1p-29 || eft[2] != 0x1p-60) return "two_product is not error-free";
  if (eft[3] != 0.0) return "a*b+c was fused into an fma despite `precise`";
  if (eft[4] != 0x1p-60) return "two_sum is not error-free";
  return {};
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
