#pragma once
// Lets the CUDA backend's per-site geometry (device_geometry.cuh, star_common.cuh,
// star_walk.cuh, star_grid.hpp) compile as plain C++ as well. Under nvcc it is device code, as
// before; under a host compiler the same source runs on the CPU, so machines without a GPU
// still test the CUDA kernels' search and star logic against CGAL
// (tests/unit/test_cuda_star_walk.cpp) and count its work (bench/src/star_work.cpp).
#include <cstdint>

#if defined(__CUDACC__)
#include <cuda_runtime.h>
#define EXPANSE_DEVICE __device__ inline
#define EXPANSE_DEVICE_FORCE __device__ __forceinline__
#define EXPANSE_DEVICE_NOINLINE __device__ __noinline__
#define EXPANSE_HOST_DEVICE __host__ __device__ inline

namespace expanse::detail::cuda {
__device__ __forceinline__ double load_readonly(const double* p) { return __ldg(p); }
__device__ __forceinline__ int load_readonly(const int* p) { return __ldg(p); }
__device__ __forceinline__ double2 load_site(const double2* points, int i) { return __ldg(points + i); }
__device__ __forceinline__ std::uint32_t load_cell_start(const std::uint32_t* starts, int c) { return __ldg(starts + c); }
__device__ __forceinline__ std::uint32_t load_readonly(const std::uint32_t* p) { return __ldg(p); }
}  // namespace expanse::detail::cuda

#else
#include <algorithm>
#include <cmath>
#define EXPANSE_DEVICE inline
#define EXPANSE_DEVICE_FORCE inline
#define EXPANSE_DEVICE_NOINLINE inline
#define EXPANSE_HOST_DEVICE inline

/// CUDA's vector type, for host builds only (host translation units that include these headers
/// must not include the CUDA runtime headers too).
struct double2 {
  double x, y;
};
inline double2 make_double2(double x, double y) { return {x, y}; }

namespace expanse::detail::cuda {
inline double load_readonly(const double* p) { return *p; }
inline int load_readonly(const int* p) { return *p; }
inline double2 load_site(const double2* points, int i) { return points[i]; }
inline std::uint32_t load_cell_start(const std::uint32_t* starts, int c) { return starts[c]; }
inline std::uint32_t load_readonly(const std::uint32_t* p) { return *p; }
using std::fabs;
using std::fmax;
using std::fmin;
using std::isfinite;
using std::max;
using std::min;
using std::sqrt;
}  // namespace expanse::detail::cuda
#endif
