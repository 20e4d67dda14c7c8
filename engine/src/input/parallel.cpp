#include "input/parallel.hpp"

#include <condition_variable>
#include <exception>
#include <mutex>
#include <thread>
#include <utility>

#if defined(__linux__)
#include <sys/mman.h>
#endif

#include "support/tuning.hpp"

namespace expanse::detail {
namespace {

std::atomic<std::size_t> threads_override{0};

// Set while this thread runs a task of a parallel pass: a pass started inside one runs its
// tasks on the calling thread (the others are busy with the outer pass already).
thread_local bool in_parallel_task = false;

// Runs tasks [0, count) on `threads` threads (the caller and threads - 1 started here),
// collecting the first exception of each task.
void run_on_new_threads(std::size_t count, std::size_t threads, void (*task)(void*, std::size_t), void* context,
                        std::vector<std::exception_ptr>& errors) {
  std::atomic<std::size_t> next{0};
  const auto drain = [&] {
    in_parallel_task = true;
    for (std::size_t i = next.fetch_add(1); i < count; i = next.fetch_add(1)) {
      try {
        task(context, i);
      } catch (...) {
        errors[i] = std::current_exception();
      }
    }
    in_parallel_task = false;
  };
  std::vector<std::thread> helpers;
  for (std::size_t t = 1; t < threads; ++t) helpers.emplace_back(drain);
  drain();
  for (auto& t : helpers) t.join();
}

// Workers started once and kept: a pass over 16M sites takes a few milliseconds on 16 cores,
// about what starting and joining 15 threads for every pass would cost. One job at a time;
// the caller works on it too. A pass started inside a task runs on its caller alone.
class Pool {
 public:
  static Pool& instance() {
    static Pool pool;
    return pool;
  }

  // False when busy (a concurrent call on another thread): parallel_tasks then starts threads
  // of its own.
  bool run(std::size_t count, std::size_t threads, void (*task)(void*, std::size_t), void* context) {
    std::unique_lock<std::mutex> busy(busy_, std::try_to_lock);
    if (!busy.owns_lock()) return false;
    std::vector<std::exception_ptr> errors(count);
    {
      std::lock_guard<std::mutex> lock(mutex_);
      while (workers_.size() + 1 < threads) workers_.emplace_back([this] { work(); });
      job_ = {task, context, count, &errors};
      next_.store(0);
      helpers_wanted_ = std::min(threads, count) - 1;
      helpers_active_ = 0;
      ++generation_;
    }
    wake_.notify_all();
    drain();
    {
      std::unique_lock<std::mutex> lock(mutex_);
      // Helpers that joined have claimed their last task; wait until they have finished it.
      helpers_wanted_ = 0;
      done_.wait(lock, [&] { return helpers_active_ == 0; });
      job_ = {};
    }
    for (auto& e : errors) {
      if (e) std::rethrow_exception(e);
    }
    return true;
  }

  ~Pool() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
    }
    wake_.notify_all();
    for (auto& t : workers_) t.join();
  }

 private:
  struct Job {
    void (*task)(void*, std::size_t) = nullptr;
    void* context = nullptr;
    std::size_t count = 0;
    std::vector<std::exception_ptr>* errors = nullptr;
  };

  void drain() {
    in_parallel_task = true;
    for (std::size_t i = next_.fetch_add(1); i < job_.count; i = next_.fetch_add(1)) {
      try {
        job_.task(job_.context, i);
      } catch (...) {
        (*job_.errors)[i] = std::current_exception();
      }
    }
    in_parallel_task = false;
  }

  void work() {
    std::size_t seen = 0;
    std::unique_lock<std::mutex> lock(mutex_);
    while (true) {
      wake_.wait(lock, [&] { return stop_ || (generation_ != seen && helpers_wanted_ > 0); });
      if (stop_) return;
      seen = generation_;
      --helpers_wanted_;
      ++helpers_active_;
      lock.unlock();
      drain();
      lock.lock();
      if (--helpers_active_ == 0) done_.notify_all();
    }
  }

  std::mutex busy_;
  std::mutex mutex_;
  std::condition_variable wake_, done_;
  std::vector<std::thread> workers_;
  Job job_;
  std::atomic<std::size_t> next_{0};
  std::size_t generation_ = 0;
  std::size_t helpers_wanted_ = 0;
  std::size_t helpers_active_ = 0;
  bool stop_ = false;
};

}  // namespace

std::size_t host_threads() {
  if (const std::size_t set = threads_override.load()) return set;
  if (const std::size_t tuned = host::tuning().threads) return tuned;
  return std::max(1u, std::thread::hardware_concurrency());
}

void set_host_threads(std::size_t threads) { threads_override.store(threads); }

void parallel_tasks(std::size_t count, void (*task)(void*, std::size_t), void* context) {
  if (count == 0) return;
  const std::size_t threads = std::min(host_threads(), count);
  if (threads > 1 && !in_parallel_task) {
    if (Pool::instance().run(count, threads, task, context)) return;
    // Another thread's pass holds the pool (the Vulkan backend uploads the input while the
    // pipeline finds the hull): threads of this pass's own. On one thread, the hull's pass over
    // 16.8M points took 60-97 ms instead of ~25 beside the upload (H100 host, 2026-11-25).
    std::vector<std::exception_ptr> errors(count);
    run_on_new_threads(count, threads, task, context, errors);
    for (const std::exception_ptr& e : errors)
      if (e) std::rethrow_exception(e);
    return;
  }
  std::exception_ptr first;
  for (std::size_t i = 0; i < count; ++i) {
    try {
      task(context, i);
    } catch (...) {
      if (!first) first = std::current_exception();
    }
  }
  if (first) std::rethrow_exception(first);
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
