#pragma once
// CUDA interop: triangulate points that already live in device memory, with every device
// operation of the CUDA backend enqueued on the caller's stream. The only public header that
// mentions CUDA types; include it only when Expanse was built with its CUDA backend
// (expanse::describe_backends() reports it as compiled).
#include <cuda_runtime_api.h>

#include <cstddef>

#include "expanse/mesh.hpp"
#include "expanse/options.hpp"

namespace expanse::cuda {

/// Delaunay triangulation of `count` points stored on the current device as interleaved
/// (x, y) doubles at `device_xy` (the layout of an array of expanse::Point2 or double2).
/// Preconditions: device_xy is device (or managed) memory readable on `stream`'s device and
/// stays valid and unmodified until the call returns; coordinates finite.
/// All device work, including the copy of the points, runs on `stream` (nullptr: the legacy
/// default stream); the call returns when the mesh is on the host. The pipeline stages that
/// are host-side in every backend (validation, duplicate merging, hull, seam completion) run
/// on the host as in expanse::triangulate. options.backend is ignored: the CUDA backend is used.
/// Throws Error(backend_unavailable) without a CUDA device, Error(device_error) for a failed
/// CUDA call (native_code() is the cudaError_t), Error(too_large) when the input cannot fit.
Mesh triangulate_device(const double* device_xy, std::size_t count, cudaStream_t stream,
                        const Options& options = {});

}  // namespace expanse::cuda
