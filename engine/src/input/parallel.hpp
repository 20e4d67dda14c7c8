#pragma once
// The host's O(n) passes (validation, Morton sort, hull filter, bucket tree, audit, output),
// which a GPU backend otherwise waits on, run on every host thread: work is cut into
// chunks or tasks numbered in order, so a result never depends on how many threads ran them.
//
// Large buffers cost more to fault in than to fill (a fresh page is zeroed by the kernel on
// first touch, one thread at a time unless several threads touch it): HostVector does not
// zero on resize, and the pass that first writes a buffer should be a parallel one.
#include <algorithm>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>
#include <type_traits>
#include <utility>
#include <vector>

namespace expanse::detail {

/// Threads the host passes may use: set_host_threads()'s value if nonzero, else
/// host::tuning().threads ($EXPANSE_HOST_THREADS) if nonzero, else every hardware thread.
/// Results never depend on it (tests and benchmarks set it to compare).
std::size_t host_threads();
void set_host_threads(std::size_t threads);

/// Runs task(i) for every i in [0, count) on up to host_threads() threads (the caller is one
/// of them) and returns when all are done. Tasks are handed out in order as threads free up.
/// Exceptions are rethrown here, the one of the lowest i. A call from inside a task runs its
/// tasks on the calling thread; a call from another thread of the program while a pass runs
/// gets threads of its own.
void parallel_tasks(std::size_t count, void (*run)(void*, std::size_t), void* context);

template <class Task>
void parallel_tasks(std::size_t count, Task&& task) {
  using T = std::remove_reference_t<Task>;
  parallel_tasks(count, [](void* c, std::size_t i) { (*static_cast<T*>(c))(i); },
                 const_cast<void*>(static_cast<const void*>(std::addressof(task))));
}

/// Number of chunks parallel_chunks() will use for n items (1 below a size where threads pay).
inline std::size_t chunk_count(std::size_t n, std::size_t min_per_chunk = std::size_t{1} << 16) {
  return std::max<std::size_t>(1, std::min(host_threads(), n / min_per_chunk));
}

/// Calls work(chunk, begin, end) for each of `chunks` chunks, concurrently; chunks are in order
/// and cover [0, n). Exceptions: as parallel_tasks (the first chunk's first).
template <class Work>
void parallel_chunks(std::size_t n, std::size_t chunks, Work&& work) {
  if (chunks <= 1) {
    work(std::size_t{0}, std::size_t{0}, n);
    return;
  }
  parallel_tasks(chunks, [&](std::size_t c) { work(c, n * c / chunks, n * (c + 1) / chunks); });
}

/// parallel_chunks with chunk_count(n) chunks.
template <class Work>
void parallel_chunks(std::size_t n, Work&& work) {
  parallel_chunks(n, chunk_count(n), std::forward<Work>(work));
}

/// std::allocator that leaves trivially copyable elements uninitialised on resize (no zeroing
/// pass): the caller writes every element before reading it.
template <class T>
struct UninitializedAllocator : std::allocator<T> {
  using value_type = T;
  template <class U>
  struct rebind {
    using other = UninitializedAllocator<U>;
  };
  UninitializedAllocator() noexcept = default;
  template <class U>
  UninitializedAllocator(const UninitializedAllocator<U>&) noexcept {}
  template <class U>
  void construct(U* p) noexcept(std::is_nothrow_default_constructible_v<U>) {
    if constexpr (!(std::is_trivially_copyable_v<U> && std::is_trivially_destructible_v<U>)) ::new (static_cast<void*>(p)) U;
  }
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};
template <class T, class U>
bool operator==(const UninitializedAllocator<T>&, const UninitializedAllocator<U>&) noexcept {
  return true;
}

/// A vector whose resize() leaves new elements unwritten (see UninitializedAllocator).
template <class T>
using HostVector = std::vector<T, UninitializedAllocator<T>>;

/// The prefix sum of a stable parallel distribution. counts[c * buckets + d] holds how many of
/// chunk c's elements go to bucket d; on return it holds the first slot chunk c writes in bucket
/// d (buckets in order, and within a bucket the chunks in order). Returns where each bucket
/// starts, with the total last (buckets + 1 entries).
std::vector<std::size_t> distribution_slots(std::vector<std::uint32_t>& counts, std::size_t chunks,
                                            std::size_t buckets);

/// Asks the kernel for transparent huge pages over [begin, begin + bytes) where it leaves that
/// to the program (THP "madvise" mode): a 2 MiB page is one fault instead of 512. A hint only.
void advise_huge_pages(void* begin, std::size_t bytes);

/// v.resize(n) for a HostVector (its new elements unwritten), with huge pages asked for: for a
/// large buffer that a parallel pass writes first, in any order (2 MiB faults, not 4 KiB).
template <class T>
void resize_for_parallel_write(HostVector<T>& v, std::size_t n) {
  const std::size_t old_size = v.size();
  v.resize(n);
  if (n > old_size) advise_huge_pages(v.data() + old_size, (n - old_size) * sizeof(T));
}

/// Faults in the pages over [begin, begin + bytes) that memory we own covers, writable, in one
/// system call where the kernel offers one (false: it did nothing, touch the pages instead).
/// The contents do not change, except that begin[0] is written (as 0).
bool populate_pages(void* begin, std::size_t bytes);

/// Faults in the pages of v's storage from [v.size(), capacity) on all threads, before a
/// sequential pass (std::vector's zeroing resize) touches them.
template <class T, class A>
void prefault_capacity(std::vector<T, A>& v) {
  static_assert(std::is_trivially_copyable_v<T>);
  auto* begin = reinterpret_cast<unsigned char*>(v.data() + v.size());
  const std::size_t bytes = (v.capacity() - v.size()) * sizeof(T);
  advise_huge_pages(begin, bytes);
  constexpr std::size_t page = 4096;
  // Chunks of at least 2 MiB (a huge page): with chunk_count's default of 2^16 items, 402 MB
  // of pages made one chunk, and each vector was faulted in on one thread.
  const std::size_t pages = bytes / page;
  parallel_chunks(pages, chunk_count(pages, 512), [&](std::size_t, std::size_t first, std::size_t last) {
    if (populate_pages(begin + first * page, (last - first) * page)) return;
    for (std::size_t p = first; p < last; ++p) begin[p * page] = 0;
  });
}

/// v.resize(n) for a std::vector of trivially copyable elements, its new pages faulted in on
/// all threads first (the zeroing pass then runs over memory that is already there).
template <class T>
void resize_prefaulted(std::vector<T>& v, std::size_t n) {
  if (n > v.capacity()) {
    v.reserve(n);
    prefault_capacity(v);
  }
  v.resize(n);
}

/// v.reserve(capacity) for a std::vector of trivially copyable elements, the new storage
/// faulted in on all threads before the elements move there.
template <class T>
void reserve_prefaulted(std::vector<T>& v, std::size_t capacity) {
  if (capacity <= v.capacity()) return;
  std::vector<T> bigger;
  bigger.reserve(capacity);
  prefault_capacity(bigger);
  bigger.insert(bigger.end(), v.begin(), v.end());
  v.swap(bigger);
}

}  // namespace expanse::detail
