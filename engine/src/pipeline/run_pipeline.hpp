#pragma once
// The pipeline behind expanse::Triangulator, for callers that bring their own backend (the
// interop entry points: a Vulkan backend on the application's device).
#include <span>

#include "backends/backend.hpp"
#include "expanse/mesh.hpp"
#include "expanse/options.hpp"
#include "expanse/types.hpp"

namespace expanse::detail {

/// Throws Error(internal) unless the host's floating-point arithmetic is exact (no FMA
/// contraction, no flushed subnormals). Checked once per process; Triangulator calls it.
void require_exact_arithmetic();

/// Triangulator::triangulate with `backend` growing the front; options.backend and
/// options.device are not looked at. Same contract and output as expanse::triangulate.
Mesh run_pipeline(Backend& backend, const Options& options, std::span<const Point2> points);

/// The same into `mesh`, whose vectors' storage the backend may fill again (GrowInput::recycled);
/// `mesh` is unchanged if the input is refused, and empty after any later error.
void run_pipeline(Backend& backend, const Options& options, std::span<const Point2> points, Mesh& mesh);

}  // namespace expanse::detail
