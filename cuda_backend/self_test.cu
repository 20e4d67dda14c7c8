// Start-up self-test: the error-free transformations and predicates, run on the device and
// compared with values known exactly. A driver, compiler flag or JIT that contracts a*b+c into
// an fma, flushes subnormals or rounds differently fails here instead of corrupting meshes.
#include <cmath>
#include <string>

#include "cuda_internal.hpp"
#include "device_geometry.cuh"

namespace expanse::detail::cuda {
namespace {

constexpr int kChecks = 12;

__global__ void self_test_kernel(double* out) {
  if (threadIdx.x != 0 || blockIdx.x != 0) return;
  double e = 0.0;
  // two_sum keeps what rounding drops.
  out[0] = ex::two_sum(1.0, 0x1p-60, e);
  out[1] = e;
  // two_product: (1 + 2^-30)^2 = 1 + 2^-29 + 2^-60.
  out[2] = ex::two_product(1.0 + 0x1p-30, 1.0 + 0x1p-30, e);
  out[3] = e;
  // Gradual underflow must survive (no flush to zero): 2^-1074 * 2 = 2^-1073.
  volatile double tiny = 0x1p-1074;
  out[4] = ex::mul(tiny, 2.0);
  // Exactly collinear and exactly cocircular integer configurations.
  out[5] = orient(make_double2(0.5, 0.5), make_double2(12.0, 12.0), make_double2(24.0, 24.0));
  out[6] = ex::incircle_certified(0, 0, 1, 0, 1, 1, 0, 1);
  out[7] = incircle_perturbed(make_double2(0, 0), make_double2(1, 0), make_double2(1, 1), make_double2(0, 1));
  // Collinear in the reals, not necessarily in binary64: the filter cannot decide, the exact
  // path must agree with the host's.
  out[8] = orient(make_double2(0.1, 0.1), make_double2(0.2, 0.3), make_double2(0.3, 0.5));
  out[9] = ex::orient2d_expansion(0.1, 0.1, 0.2, 0.3, 0.3, 0.5);
  // The compiler must not fuse this plain expression (the -fmad=false guard): with an fma the
  // result would be the exact residual 2^-60 instead of 0.
  volatile double a = 1.0 + 0x1p-30;
  const double p = a * a;
  out[10] = a * a - p;
  out[11] = compare_distance(make_double2(0, 0), make_double2(3, 4), make_double2(5, 0));
}

}  // namespace

bool device_self_test(cudaStream_t stream, std::string* why) {
  double* d_out = nullptr;
  EXPANSE_CUDA(cudaMallocAsync(reinterpret_cast<void**>(&d_out), kChecks * sizeof(double), stream));
  double out[kChecks] = {};
  self_test_kernel<<<1, 32, 0, stream>>>(d_out);
  const cudaError_t launch = cudaGetLastError();
  if (launch != cudaSuccess) {
    cudaFreeAsync(d_out, stream);
    throw_cuda(launch, "self_test_kernel<<<>>>", __FILE__, __LINE__);
  }
  EXPANSE_CUDA(cudaMemcpyAsync(out, d_out, sizeof(out), cudaMemcpyDeviceToHost, stream));
  EXPANSE_CUDA(cudaFreeAsync(d_out, stream));
  EXPANSE_CUDA(cudaStreamSynchronize(stream));
  // The host evaluates the same exact routine (compiled without contraction) for comparison.
  const double host_orient = static_cast<double>(ex::orient2d_expansion(0.1, 0.1, 0.2, 0.3, 0.3, 0.5));
  const struct {
    double expected;
    const char* what;
  } expect[kChecks] = {
      {1.0, "two_sum result"},
      {0x1p-60, "two_sum error term"},
      {1.0 + 0x1p-29, "two_product result"},
      {0x1p-60, "two_product error term (fma contraction or split broken)"},
      {0x1p-1073, "gradual underflow (subnormals flushed)"},
      {0.0, "orient2d of exactly collinear points"},
      {0.0, "incircle certificate of a cocircular square"},
      {1.0, "CGAL perturbation of a cocircular square"},
      {host_orient, "orient2d expansion path (device disagrees with host)"},
      {host_orient, "orient2d_expansion (device disagrees with host)"},
      {0.0, "no fma contraction of a*a - p"},
      {0.0, "exact distance comparison (3,4) vs (5,0)"},
  };
  for (int i = 0; i < kChecks; ++i) {
    if (!(out[i] == expect[i].expected)) {
      if (why)
        *why = std::string(expect[i].what) + ": got " + std::to_string(out[i]) + ", expected " +
               std::to_string(expect[i].expected);
      return false;
    }
  }
  return true;
}

}  // namespace expanse::detail::cuda
