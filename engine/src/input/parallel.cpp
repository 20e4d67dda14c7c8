#include "input/parallel.hpp"

#include <omp.h>

#include <exception>
#include <mutex>
#include <thread>
#include <utility>

#include "support/tuning.hpp"

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace expanse::detail {
namespace {

std::atomic<std::size_t> threads_override{0};

// The exception of the lowest task that threw: OpenMP lets none leave a parallel region, so
// each task's is caught and the lowest kept, whichever thread ran it.
class FirstError {
 public:
  explicit FirstError(std::size_t count) : task_(count) {}
  void keep(std::size_t task, std::exception_ptr error) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (task < task_) {
      task_ = task;
      error_ = std::move(error);
    }
  }
  void rethrow() const {
    if (error_) std::rethrow_exception(error_);
  }

 private:
  std::mutex mutex_;
  std::size_t task_;
  std::exception_ptr error_;
};

}  // namespace

std::size_t host_threads() {
  if (const std::size_t set = threads_override.load()) return set;
  if (const std::size_t from_environment = host::tuning().threads) return from_environment;
  return std::max(1u, std::thread::hardware_concurrency());
}

void set_host_threads(std::size_t threads) { threads_override.store(threads); }

void parallel_tasks(std::size_t count, void (*task)(void*, std::size_t), void* context) {
  if (count == 0) return;
  const std::size_t threads = std::min(host_threads(), count);
  FirstError first(count);
  // Inside a task (omp_in_parallel) the other threads are busy with the outer pass: the tasks
  // run on this thread. A pass started on another thread of the program while one runs (the Vulkan
  // backend uploads the input while the pipeline finds the hull) gets a team of its own.
  const bool spread = threads > 1 && !omp_in_parallel();
  // dynamic, 1: tasks handed out in order as threads free up (they differ in size).
#pragma omp parallel for if (spread) num_threads(static_cast<int>(threads)) schedule(dynamic, 1)
  for (std::size_t i = 0; i < count; ++i) {
    try {
      task(context, i);
    } catch (...) {
      first.keep(i, std::current_exception());
    }
  }
  first.rethrow();
}

std::vector<std::size_t> distribution_slots(std::vector<std::uint32_t>& counts, std::size_t chunks,
                                            std::size_t buckets) {
  std::vector<std::size_t> start(buckets + 1, 0);
  std::size_t sum = 0;
  for (std::size_t d = 0; d < buckets; ++d) {
    start[d] = sum;
    for (std::size_t c = 0; c < chunks; ++c) sum += std::exchange(counts[c * buckets + d], static_cast<std::uint32_t>(sum));
  }
  start[buckets] = sum;
  return start;
}

void advise_huge_pages(void* begin, std::size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  constexpr std::uintptr_t huge = std::uintptr_t{2} << 20;
  const auto first = (reinterpret_cast<std::uintptr_t>(begin) + huge - 1) & ~(huge - 1);
  const auto last = (reinterpret_cast<std::uintptr_t>(begin) + bytes) & ~(huge - 1);
  if (last > first) madvise(reinterpret_cast<void*>(first), last - first, MADV_HUGEPAGE);  // a hint: errors ignored
#else
  (void)begin;
  (void)bytes;
#endif
}

bool populate_pages(void* begin, std::size_t bytes) {
#if defined(__linux__)
  // MADV_POPULATE_WRITE (Linux 5.14) faults in a range in one call instead of one trap per
  // page: 805 MB of 4 KiB pages on the 2-core VM, 2 threads, 326 -> 303 ms (THP: 40 -> 37 ms).
  constexpr int populate_write = 23;  // MADV_POPULATE_WRITE, for headers that predate it
  constexpr std::uintptr_t page = 4096;
  const auto first = (reinterpret_cast<std::uintptr_t>(begin) + page - 1) & ~(page - 1);
  const auto last = (reinterpret_cast<std::uintptr_t>(begin) + bytes) & ~(page - 1);
  if (last <= first) return false;
  if (madvise(reinterpret_cast<void*>(first), last - first, populate_write) != 0) return false;
  static_cast<volatile unsigned char*>(begin)[0] = 0;  // the page it starts in, if not aligned
  return true;
#else
  (void)begin;
  (void)bytes;
  return false;
#endif
}

}  // namespace expanse::detail
