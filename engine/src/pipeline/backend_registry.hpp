#pragma once
// Picks and creates backends by kind; knows which are compiled in.
#include <memory>

#include "backends/backend.hpp"

namespace expanse::detail {

/// Creates the backend for `kind` (automatic resolves through default_backend()). Throws
/// Error(backend_unavailable) with the reason when it is not compiled in or has no device.
std::unique_ptr<Backend> make_backend(BackendKind kind, int device);

}  // namespace expanse::detail
