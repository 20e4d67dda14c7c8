#pragma once
// Splits [0, n) into one contiguous chunk per hardware thread for the host's O(n) passes
// (validation, scaling, Morton codes, radix sort), which a GPU backend otherwise waits on.
#include <algorithm>
#include <cstddef>
#include <thread>
#include <vector>

namespace expanse::detail {

/// Number of chunks parallel_chunks() will use for n items (1 below a size where threads pay).
inline std::size_t chunk_count(std::size_t n) {
  constexpr std::size_t min_per_chunk = std::size_t{1} << 17;
  const std::size_t hardware = std::max(1u, std::thread::hardware_concurrency());
  return std::max<std::size_t>(1, std::min(hardware, n / min_per_chunk));
}

/// Calls work(chunk, begin, end) for each chunk, concurrently; chunks are in order and cover
/// [0, n). Exceptions thrown by work are rethrown here (the first chunk's first).
template <class Work>
void parallel_chunks(std::size_t n, Work&& work) {
  const std::size_t chunks = chunk_count(n);
  const auto bounds = [&](std::size_t c) { return n * c / chunks; };
  if (chunks == 1) {
    work(std::size_t{0}, std::size_t{0}, n);
    return;
  }
  std::vector<std::exception_ptr> errors(chunks);
  std::vector<std::thread> threads;
  threads.reserve(chunks - 1);
  for (std::size_t c = 1; c < chunks; ++c) {
    threads.emplace_back([&, c] {
      try {
        work(c, bounds(c), bounds(c + 1));
      } catch (...) {
        errors[c] = std::current_exception();
      }
    });
  }
  try {
    work(std::size_t{0}, std::size_t{0}, bounds(1));
  } catch (...) {
    errors[0] = std::current_exception();
  }
  for (auto& t : threads) t.join();
  for (auto& e : errors) {
    if (e) std::rethrow_exception(e);
  }
}

}  // namespace expanse::detail
