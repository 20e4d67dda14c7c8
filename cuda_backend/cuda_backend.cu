// The CUDA Backend: device selection, the one stream, pinned staging, stage timing, and the
// dispatch to the per-site or block layout.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <thread>

#include "cuda_internal.hpp"

namespace expanse::detail::cuda {

// ---- Pinned staging ---------------------------------------------------------------------------

namespace {

/// memcpy spread over `threads` threads: one core copies ~10 GB/s, far below what PCIe delivers.
void parallel_copy(void* dst, const void* src, std::size_t bytes, std::size_t threads) {
  constexpr std::size_t per_thread_min = std::size_t{2} << 20;
  const unsigned hw = std::max(1u, std::thread::hardware_concurrency());
  const std::size_t parts =
      std::min<std::size_t>({threads, hw, std::max<std::size_t>(1, bytes / per_thread_min)});
  if (parts <= 1) {
    std::memcpy(dst, src, bytes);
    return;
  }
  const std::size_t step = (bytes + parts - 1) / parts;
  std::vector<std::thread> workers;
  workers.reserve(parts - 1);
  for (std::size_t p = 1; p < parts; ++p) {
    const std::size_t begin = p * step;
    if (begin >= bytes) break;
    const std::size_t len = std::min(step, bytes - begin);
    workers.emplace_back([=] { std::memcpy(static_cast<char*>(dst) + begin, static_cast<const char*>(src) + begin, len); });
  }
  std::memcpy(dst, src, std::min(step, bytes));
  for (auto& w : workers) w.join();
}

}  // namespace

PinnedStaging::PinnedStaging(std::size_t chunk_bytes, std::size_t copy_threads)
    : chunk_(chunk_bytes), copy_threads_(copy_threads) {
  for (int b = 0; b < 2; ++b) {
    EXPANSE_CUDA(cudaHostAlloc(&buffer_[b], chunk_, cudaHostAllocDefault));
    EXPANSE_CUDA(cudaEventCreateWithFlags(&done_[b], cudaEventDisableTiming));
  }
}

PinnedStaging::~PinnedStaging() {
  for (int b = 0; b < 2; ++b) {
    if (done_[b]) cudaEventDestroy(done_[b]);
    if (buffer_[b]) cudaFreeHost(buffer_[b]);
  }
}

void PinnedStaging::upload(void* device_dst, const void* host_src, std::size_t bytes, cudaStream_t stream) {
  for (std::size_t offset = 0, k = 0; offset < bytes; offset += chunk_, ++k) {
    const int b = static_cast<int>(k & 1);
    const std::size_t len = std::min(chunk_, bytes - offset);
    // The DMA that last read this buffer must be done before we overwrite it.
    EXPANSE_CUDA(cudaEventSynchronize(done_[b]));
    parallel_copy(buffer_[b], static_cast<const char*>(host_src) + offset, len, copy_threads_);
    EXPANSE_CUDA(cudaMemcpyAsync(static_cast<char*>(device_dst) + offset, buffer_[b], len, cudaMemcpyHostToDevice, stream));
    EXPANSE_CUDA(cudaEventRecord(done_[b], stream));
  }
  bytes_moved_ += bytes;
}

void PinnedStaging::download(void* host_dst, const void* device_src, std::size_t bytes, cudaStream_t stream) {
  std::size_t pending_offset = 0, pending_len = 0;
  int pending_buffer = -1;
  for (std::size_t offset = 0, k = 0; offset < bytes; offset += chunk_, ++k) {
    const int b = static_cast<int>(k & 1);
    const std::size_t len = std::min(chunk_, bytes - offset);
    EXPANSE_CUDA(cudaMemcpyAsync(buffer_[b], static_cast<const char*>(device_src) + offset, len, cudaMemcpyDeviceToHost, stream));
    EXPANSE_CUDA(cudaEventRecord(done_[b], stream));
    // While this chunk crosses the bus, drain the previous one.
    if (pending_buffer >= 0) {
      EXPANSE_CUDA(cudaEventSynchronize(done_[pending_buffer]));
      parallel_copy(static_cast<char*>(host_dst) + pending_offset, buffer_[pending_buffer], pending_len, copy_threads_);
    }
    pending_buffer = b, pending_offset = offset, pending_len = len;
  }
  if (pending_buffer >= 0) {
    EXPANSE_CUDA(cudaEventSynchronize(done_[pending_buffer]));
    parallel_copy(static_cast<char*>(host_dst) + pending_offset, buffer_[pending_buffer], pending_len, copy_threads_);
  }
  bytes_moved_ += bytes;
}

PinnedInPlace::~PinnedInPlace() {
  for (void* range : ranges_) cudaHostUnregister(range);  // a destructor cannot report failure
}

bool PinnedInPlace::pin(void* data, std::size_t bytes) {
  if (data == nullptr || bytes == 0) return false;
  if (cudaHostRegister(data, bytes, cudaHostRegisterDefault) != cudaSuccess) {
    cudaGetLastError();  // clears the refusal: the ring copies instead
    return false;
  }
  ranges_.push_back(data);
  return true;
}

bool PinnedInPlace::pinned(const void* data) const {
  return std::find(ranges_.begin(), ranges_.end(), data) != ranges_.end();
}

// ---- Stage timer ------------------------------------------------------------------------------

StageTimer::~StageTimer() {
  for (auto& m : marks_) {
    if (m.start) cudaEventDestroy(m.start);
    if (m.stop) cudaEventDestroy(m.stop);
  }
}

void StageTimer::begin(const char* name) {
  Mark m;
  m.name = name;
  EXPANSE_CUDA(cudaEventCreate(&m.start));
  EXPANSE_CUDA(cudaEventCreate(&m.stop));
  EXPANSE_CUDA(cudaEventRecord(m.start, stream_));
  marks_.push_back(std::move(m));
}

void StageTimer::end() { EXPANSE_CUDA(cudaEventRecord(marks_.back().stop, stream_)); }

std::vector<StageTime> StageTimer::collect() {
  std::vector<StageTime> out;
  if (marks_.empty()) return out;
  EXPANSE_CUDA(cudaEventSynchronize(marks_.back().stop));
  for (auto& m : marks_) {
    float ms = 0.0f;
    EXPANSE_CUDA(cudaEventElapsedTime(&ms, m.start, m.stop));
    out.push_back({m.name, static_cast<double>(ms)});
  }
  return out;
}

StreamTimeline::StreamTimeline(bool on) : on_(on) {}

StreamTimeline::~StreamTimeline() {
  for (auto& m : marks_) cudaEventDestroy(m.second);
}

void StreamTimeline::mark(const char* name, cudaStream_t stream) {
  if (!on_) return;
  cudaEvent_t e = nullptr;
  EXPANSE_CUDA(cudaEventCreate(&e));
  EXPANSE_CUDA(cudaEventRecord(e, stream));
  marks_.emplace_back(name, e);
}

void StreamTimeline::print(const char* title) {
  if (!on_ || marks_.empty()) return;
  std::fprintf(stderr, "%s:", title);
  for (auto& [name, e] : marks_) {
    EXPANSE_CUDA(cudaEventSynchronize(e));
    float ms = 0.0f;
    EXPANSE_CUDA(cudaEventElapsedTime(&ms, marks_.front().second, e));
    std::fprintf(stderr, " %s %.2f;", name.c_str(), ms);
  }
  std::fprintf(stderr, "\n");
}

RunCounters& last_run_counters() {
  thread_local RunCounters counters;
  return counters;
}

cudaStream_t& borrowed_stream() {
  thread_local cudaStream_t stream = nullptr;
  return stream;
}

// ---- The backend ------------------------------------------------------------------------------

namespace {

std::string unavailable_reason(cudaError_t code) {
  return std::string("CUDA backend: no usable device (") + cudaGetErrorName(code) + ": " + cudaGetErrorString(code) + ")";
}

int device_count_or_throw() {
  int count = 0;
  const cudaError_t code = cudaGetDeviceCount(&count);
  if (code != cudaSuccess) {
    cudaGetLastError();  // clear the sticky-free error so later calls start clean
    throw Error(ErrorCode::backend_unavailable, unavailable_reason(code), static_cast<std::int64_t>(code));
  }
  if (count == 0) throw Error(ErrorCode::backend_unavailable, "CUDA backend: no CUDA device found");
  return count;
}

}  // namespace

void require_device_memory(std::size_t bytes, std::size_t count, const char* what) {
  const std::size_t need = bytes + (std::size_t{64} << 20);
  std::size_t free_bytes = 0, total_bytes = 0;
  EXPANSE_CUDA(cudaMemGetInfo(&free_bytes, &total_bytes));
  if (need > free_bytes)
    throw Error(ErrorCode::too_large, "CUDA backend: " + std::to_string(count) + " " + what + " need about " +
                                          std::to_string(need >> 20) + " MiB of device memory, " +
                                          std::to_string(free_bytes >> 20) + " MiB free");
}

namespace {

class CudaBackend final : public Backend {
 public:
  explicit CudaBackend(int device) {
    const int count = device_count_or_throw();
    if (device < 0) {
      // The device with the most multiprocessors: the discrete one on mixed machines.
      int best = 0, best_sms = -1;
      for (int d = 0; d < count; ++d) {
        int sms = 0;
        EXPANSE_CUDA(cudaDeviceGetAttribute(&sms, cudaDevAttrMultiProcessorCount, d));
        if (sms > best_sms) best = d, best_sms = sms;
      }
      device = best;
    }
    if (device >= count)
      throw Error(ErrorCode::invalid_argument, "CUDA backend: device " + std::to_string(device) + " does not exist (" +
                                                   std::to_string(count) + " found)");
    ctx_.device = device;
    EXPANSE_CUDA(cudaSetDevice(device));
    cudaDeviceProp props{};
    EXPANSE_CUDA(cudaGetDeviceProperties(&props, device));
    ctx_.name = props.name;
    ctx_.total_memory = props.totalGlobalMem;
    ctx_.multiprocessors = props.multiProcessorCount;
    // Keep pool memory between calls: repeated triangulations then allocate nothing.
    cudaMemPool_t pool = nullptr;
    EXPANSE_CUDA(cudaDeviceGetDefaultMemPool(&pool, device));
    std::uint64_t threshold = std::numeric_limits<std::uint64_t>::max();
    EXPANSE_CUDA(cudaMemPoolSetAttribute(pool, cudaMemPoolAttrReleaseThreshold, &threshold));
    if (borrowed_stream()) {
      ctx_.stream = borrowed_stream();
    } else {
      EXPANSE_CUDA(cudaStreamCreateWithFlags(&ctx_.stream, cudaStreamNonBlocking));
      ctx_.own_stream = true;
    }
    std::string why;
    if (!device_self_test(ctx_.stream, &why))
      throw Error(ErrorCode::device_error, "CUDA backend: device arithmetic self-test failed on " + ctx_.name + ": " + why);
    // The main ring: 64 MiB chunks drained by 16 threads. The host's copy out of pinned memory
    // is what limits a download (805 MB at 4096^2: the bus alone 15 ms, through 32 MiB chunks
    // and 8 threads 49 ms, 64 MiB and 16 threads 28 ms; H100 host).
    staging_ = std::make_unique<PinnedStaging>(std::size_t{64} << 20, 16);
    ctx_.staging = staging_.get();
    if (ctx_.own_stream) {
      EXPANSE_CUDA(cudaStreamCreateWithFlags(&ctx_.side_stream, cudaStreamNonBlocking));
      // The side ring copies while the host's pool faults in the output: fewer threads.
      side_staging_ = std::make_unique<PinnedStaging>(std::size_t{32} << 20, 8);
      ctx_.side_staging = side_staging_.get();
      int least = 0, greatest = 0;
      EXPANSE_CUDA(cudaDeviceGetStreamPriorityRange(&least, &greatest));
      EXPANSE_CUDA(cudaStreamCreateWithPriority(&ctx_.edge_stream, cudaStreamNonBlocking, greatest));
      EXPANSE_CUDA(cudaStreamCreateWithPriority(&ctx_.low_stream, cudaStreamNonBlocking, least));
    }
    EXPANSE_CUDA(cudaHostAlloc(reinterpret_cast<void**>(&ctx_.pinned_words), Context::kPinnedWords * sizeof(unsigned int),
                               cudaHostAllocDefault));
  }

  ~CudaBackend() override {
    staging_.reset();
    side_staging_.reset();
    for (cudaStream_t extra : {ctx_.side_stream, ctx_.edge_stream, ctx_.low_stream}) {
      if (!extra) continue;
      cudaStreamSynchronize(extra);
      cudaStreamDestroy(extra);
    }
    if (ctx_.pinned_words) cudaFreeHost(ctx_.pinned_words);
    if (ctx_.own_stream && ctx_.stream) {
      cudaStreamSynchronize(ctx_.stream);
      cudaStreamDestroy(ctx_.stream);
    }
  }

  BackendKind kind() const override { return BackendKind::cuda; }
  std::string device_name() const override { return ctx_.name; }

  GrowResult grow(const GrowInput& input) override {
    EXPANSE_CUDA(cudaSetDevice(ctx_.device));
    GrowResult result;
    if (input.sites.size() < 3) return result;
    if (input.layout.seeding == Layout::Seeding::paper_blocks)
      grow_paper_blocks(ctx_, input, result);
    else
      grow_per_site(ctx_, input, result);
    return result;
  }

  // Tuning::prepare_on_device (EXPANSE_CUDA_PREPARE=host) keeps the preparation on the host.
  bool prepares_sites(const Layout& layout) const override {
    return layout.seeding != Layout::Seeding::paper_blocks && tuning_from_environment().prepare_on_device;
  }

  std::optional<InputGrowResult> grow_from_input(const InputGrowInput& input) override {
    if (!prepares_sites(input.layout)) return std::nullopt;
    EXPANSE_CUDA(cudaSetDevice(ctx_.device));
    std::optional<InputGrowResult> result(std::in_place);
    if (!grow_per_site_from_input(ctx_, input, *result)) return std::nullopt;
    return result;
  }

 private:
  Context ctx_;
  std::unique_ptr<PinnedStaging> staging_, side_staging_;
};

}  // namespace

}  // namespace expanse::detail::cuda

namespace expanse::detail {

std::unique_ptr<Backend> make_cuda_backend(int device) { return std::make_unique<cuda::CudaBackend>(device); }

std::vector<DeviceDescription> list_cuda_devices() {
  const int count = cuda::device_count_or_throw();
  std::vector<DeviceDescription> out;
  for (int d = 0; d < count; ++d) {
    cudaDeviceProp props{};
    EXPANSE_CUDA(cudaGetDeviceProperties(&props, d));
    DeviceDescription desc;
    desc.index = d;
    desc.name = props.name;
    desc.type = props.integrated ? "integrated" : "discrete";
    desc.fp64 = true;  // every CUDA device has IEEE binary64 (throughput varies)
    desc.details = "compute capability " + std::to_string(props.major) + "." + std::to_string(props.minor) + ", " +
                   std::to_string(props.multiProcessorCount) + " SMs, " +
                   std::to_string(props.totalGlobalMem >> 20) + " MiB, warp " + std::to_string(props.warpSize);
    out.push_back(std::move(desc));
  }
  return out;
}

}  // namespace expanse::detail
