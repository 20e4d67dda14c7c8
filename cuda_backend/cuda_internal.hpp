#pragma once
// Host-side pieces the CUDA backend's translation units share. Internal: CUDA types are fine
// here, never in engine/include except cuda_interop.hpp.
#include <cuda_runtime_api.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "backends/backend.hpp"
#include "cuda_check.hpp"
#include "tuning.hpp"

namespace expanse::detail::cuda {

/// Two pinned buffers used alternately, so that a host memcpy of one chunk overlaps the DMA of
/// the next. Pageable copies run at ~8-13 GB/s, pinned at ~50 GB/s; the host memcpy into or out
/// of the caller's std::vector is spread over a few threads to keep up.
class PinnedStaging {
 public:
  /// copy_threads: host threads that copy each chunk between pinned and pageable memory.
  explicit PinnedStaging(std::size_t chunk_bytes = std::size_t{32} << 20, std::size_t copy_threads = 8);
  ~PinnedStaging();
  PinnedStaging(const PinnedStaging&) = delete;
  PinnedStaging& operator=(const PinnedStaging&) = delete;

  /// Host -> device, enqueued on `stream`; returns once the host source may be reused.
  void upload(void* device_dst, const void* host_src, std::size_t bytes, cudaStream_t stream);
  /// Device -> host; returns when the bytes are in host_dst.
  void download(void* host_dst, const void* device_src, std::size_t bytes, cudaStream_t stream);
  std::size_t bytes_moved() const { return bytes_moved_; }

 private:
  std::size_t chunk_;
  std::size_t copy_threads_;
  void* buffer_[2] = {nullptr, nullptr};
  cudaEvent_t done_[2] = {nullptr, nullptr};
  std::size_t bytes_moved_ = 0;
};

/// Host memory pinned where it lies (cudaHostRegister) for as long as the object lives, so that
/// a download goes straight into it at the bus's speed instead of through a staging ring. On the
/// H100's host (805 MB at 4096^2): pinning 27-29 ms, releasing 18 ms, the copy 15.3 ms
/// against 35-37 ms through the ring. A range the driver refuses is left unpinned (pinned()
/// says so) and the caller uses the ring.
class PinnedInPlace {
 public:
  PinnedInPlace() = default;
  ~PinnedInPlace();
  PinnedInPlace(const PinnedInPlace&) = delete;
  PinnedInPlace& operator=(const PinnedInPlace&) = delete;
  /// Pins [data, data + bytes); returns whether it is pinned.
  bool pin(void* data, std::size_t bytes);
  bool pinned(const void* data) const;
  bool empty() const { return ranges_.empty(); }

 private:
  std::vector<void*> ranges_;
};

/// CUDA events around named stages, read once at the end (no sync per stage).
class StageTimer {
 public:
  explicit StageTimer(cudaStream_t stream) : stream_(stream) {}
  ~StageTimer();
  StageTimer(const StageTimer&) = delete;
  StageTimer& operator=(const StageTimer&) = delete;
  void begin(const char* name);
  void end();
  /// Synchronises on the last event and returns the stage times.
  std::vector<StageTime> collect();

 private:
  struct Mark {
    std::string name;
    cudaEvent_t start = nullptr, stop = nullptr;
  };
  cudaStream_t stream_;
  std::vector<Mark> marks_;
};

/// When the work of each stream reached named points, measured from the first mark: which of
/// the streams that run side by side ends a stage. Off unless `on` (Tuning::star_timeline, a
/// diagnostic: it prints to stderr).
class StreamTimeline {
 public:
  explicit StreamTimeline(bool on);
  ~StreamTimeline();
  StreamTimeline(const StreamTimeline&) = delete;
  StreamTimeline& operator=(const StreamTimeline&) = delete;
  void mark(const char* name, cudaStream_t stream);
  /// Synchronises on every mark and prints them, in ms after the first.
  void print(const char* title);
  bool on() const { return on_; }

 private:
  bool on_ = false;
  std::vector<std::pair<std::string, cudaEvent_t>> marks_;
};

/// The device a backend runs on and the one stream all its work goes to.
struct Context {
  int device = 0;
  cudaStream_t stream = nullptr;
  bool own_stream = false;
  std::string name;
  std::size_t total_memory = 0;
  int multiprocessors = 1;
  PinnedStaging* staging = nullptr;
  /// A second stream and staging ring for copies to the host that no device work waits for
  /// (the prepared sites, while the stars grow); null when the caller lent `stream`, whose
  /// work then all stays on it.
  cudaStream_t side_stream = nullptr;
  PinnedStaging* side_staging = nullptr;
  /// A stream of the highest priority for the star walks of the sites along the grid's edge,
  /// which run alongside the rest (grow_per_site); null when the caller lent `stream`.
  cudaStream_t edge_stream = nullptr;
  /// A stream of the main stream's priority (the lowest), beside it, for the edge's retry
  /// (grow_per_site); null when the caller lent `stream`.
  cudaStream_t low_stream = nullptr;
  /// 0..15: counters and sizes; 16..31: the two quantile guide keys (16 is 8-byte aligned).
  static constexpr int kPinnedWords = 32;
  unsigned int* pinned_words = nullptr;  ///< kPinnedWords pinned words for small asynchronous read-backs
};

/// Sites already on the device in the order of the host's SiteSet, and the hull in their ids
/// (prepare_on_device): grow_per_site takes them instead of uploading input.sites.
struct SitesOnDevice {
  const double2* points = nullptr;
  const int* hull = nullptr;
  /// Runs of equal Morton codes longer than the merge searches pairwise (a cluster finer than
  /// the quantisation), in no spatial order (the host's preparation puts them in (x, y) order).
  bool unordered_runs = false;
};

/// Per-site star layout (docs/algorithm.md, "GPU, per-site seeding").
void grow_per_site(Context& ctx, const GrowInput& input, GrowResult& result, const SitesOnDevice* on_device = nullptr);

/// The per-site layout from raw input: the device scales, merges duplicates and orders the
/// sites (prepare_on_device.cu), fills result.sites and result.hull as prepare_sites and
/// convex_hull would, and grows. False, having consumed nothing, for 2^30 points or more (the
/// host's path refuses them with its error).
bool grow_per_site_from_input(Context& ctx, const InputGrowInput& input, InputGrowResult& result);

/// Throws Error(too_large), naming `count` `what`, unless about `bytes` of device memory (and a
/// margin) are free: fail early, with the right error, when a working set cannot fit.
void require_device_memory(std::size_t bytes, std::size_t count, const char* what);
/// The paper's block layout with halo (docs/algorithm.md, "GPU, the paper's layout").
void grow_paper_blocks(Context& ctx, const GrowInput& input, GrowResult& result);

/// Runs the error-free transformations and predicates on the device against values known
/// exactly; false (with the reason) when the device arithmetic cannot be trusted.
bool device_self_test(cudaStream_t stream, std::string* why);

/// What the last grow() on this thread moved and evaluated (for the benchmark's floor count).
struct RunCounters {
  std::uint64_t predicates = 0;  ///< orient2d + incircle evaluations in the apex searches
  std::uint64_t bytes_to_device = 0;
  std::uint64_t bytes_to_host = 0;
  std::uint64_t triangles = 0;
  std::uint64_t max_cells_per_site = 0;     ///< the longest star's bucket visits (per-site layout)
  std::uint64_t sites_over_4096_cells = 0;  ///< stars that visited more than 4096 buckets
  std::uint64_t sites_over_budget = 0;      ///< stars deferred because their search ran away
  std::uint64_t open_pairs_linked = 0;      ///< edges between two deferred sites' triangles, linked
  std::uint64_t open_edges = 0;             ///< edges the device audit found open inside the hull
  bool uniform_cells = false;               ///< the evenness test chose uniform cells
  bool short_morton_sort = false;           ///< the device's preparation sorted by short keys
  bool merge_hash_tables = false;           ///< its merge found a run too long to look back through
};
RunCounters& last_run_counters();

/// A stream that the interop entry point lends to the next backends created on this thread.
cudaStream_t& borrowed_stream();

/// Device memory with stream-ordered lifetime (cudaMallocAsync from a pool that keeps its
/// memory between calls, so repeated triangulations allocate nothing).
template <class T>
class DeviceArray {
 public:
  DeviceArray(std::size_t count, cudaStream_t stream) : stream_(stream), count_(count) {
    if (count_ > 0) EXPANSE_CUDA(cudaMallocAsync(reinterpret_cast<void**>(&ptr_), count_ * sizeof(T), stream_));
  }
  ~DeviceArray() {
    if (ptr_) cudaFreeAsync(ptr_, stream_);
  }
  DeviceArray(const DeviceArray&) = delete;
  DeviceArray& operator=(const DeviceArray&) = delete;
  /// Exchanges the two arrays' memory (and streams): a buffer that already holds the contents
  /// another is to hold takes its place instead of a copy.
  void swap(DeviceArray& other) noexcept {
    std::swap(stream_, other.stream_);
    std::swap(count_, other.count_);
    std::swap(ptr_, other.ptr_);
  }
  T* get() const { return ptr_; }
  std::size_t size() const { return count_; }
  std::size_t bytes() const { return count_ * sizeof(T); }

 private:
  cudaStream_t stream_;
  std::size_t count_;
  T* ptr_ = nullptr;
};

}  // namespace expanse::detail::cuda
