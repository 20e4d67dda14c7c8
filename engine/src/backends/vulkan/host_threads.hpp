#pragma once
// Host-side helpers of the Vulkan backend's passes: O(count) work split over host threads, and
// byte counts of device buffers.
#include <vulkan/vulkan.h>

#include <algorithm>
#include <cstddef>
#include <cstring>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

#include "input/parallel.hpp"

namespace expanse::detail::vk {

inline VkDeviceSize bytes_of(std::size_t count, std::size_t size) { return VkDeviceSize(count) * size; }

// Host threads for an O(count) pass: all of them for large passes, one for small ones.
inline unsigned host_workers(std::size_t count) {
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

// memcpy in one sequential stream per host thread: the access pattern write-combined (uncached)
// mapped memory needs, and page faults of a fresh destination spread over the cores.
inline void copy_on_host_threads(void* to, const void* from, std::size_t bytes) {
  detail::parallel_chunks(bytes, detail::chunk_count(bytes, std::size_t(1) << 20),
                          [&](std::size_t, std::size_t begin, std::size_t end) {
                            std::memcpy(static_cast<char*>(to) + begin,
                                        static_cast<const char*>(from) + begin, end - begin);
                          });
}

}  // namespace expanse::detail::vk
