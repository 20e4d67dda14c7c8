// expanse::cuda::triangulate_device: the caller's points and stream in, a host Mesh out.
#include "expanse/cuda_interop.hpp"

#include <vector>

#include "cuda_internal.hpp"
#include "expanse/triangulate.hpp"

namespace expanse::cuda {

Mesh triangulate_device(const double* device_xy, std::size_t count, cudaStream_t stream, const Options& options) {
  using detail::cuda::borrowed_stream;
  std::vector<Point2> points(count);
  if (count > 0) {
    EXPANSE_CUDA(cudaMemcpyAsync(points.data(), device_xy, count * sizeof(Point2), cudaMemcpyDeviceToHost, stream));
    EXPANSE_CUDA(cudaStreamSynchronize(stream));
  }
  // The backend the pipeline creates on this thread borrows the caller's stream.
  struct Lend {
    cudaStream_t previous;
    explicit Lend(cudaStream_t s) : previous(borrowed_stream()) { borrowed_stream() = s; }
    ~Lend() { borrowed_stream() = previous; }
  } lend(stream ? stream : cudaStreamLegacy);
  Options cuda_options = options;
  cuda_options.backend = BackendKind::cuda;
  return triangulate(points, cuda_options);
}

}  // namespace expanse::cuda
