#pragma once
// What every layout does after sorting ids by a key: put the points in that order, and find
// where each key's run starts (per-site cells, the paper's blocks, the device's preparation).
#include <cstdint>

namespace expanse::detail::cuda {
namespace {

/// sorted_points[i] = points[sorted_ids[i]]; rank (optional) the inverse permutation.
__global__ void gather_kernel(const int* sorted_ids, const double2* points, int n, double2* sorted_points,
                              int* rank = nullptr) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= n) return;
  const int id = sorted_ids[i];
  sorted_points[i] = points[id];
  if (rank) rank[id] = i;
}

/// cell_start[c] = the first position whose key is >= c, for c in [0, cells]; keys sorted, each
/// below `cells`.
__global__ void cell_start_kernel(const std::uint32_t* keys, int n, int cells, std::uint32_t* cell_start) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= n) return;
  const int key = static_cast<int>(keys[i]);
  const int prev = i == 0 ? -1 : static_cast<int>(keys[i - 1]);
  for (int c = prev + 1; c <= key; ++c) cell_start[c] = static_cast<std::uint32_t>(i);
  if (i == n - 1)
    for (int c = key + 1; c <= cells; ++c) cell_start[c] = static_cast<std::uint32_t>(n);
}

}  // namespace
}  // namespace expanse::detail::cuda
