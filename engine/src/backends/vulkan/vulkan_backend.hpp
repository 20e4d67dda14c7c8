#pragma once
// The Vulkan backend's internals that tests reach into (the Backend itself is created through
// make_vulkan_backend in backends/backend.hpp).
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "backends/vulkan/vk_context.hpp"

namespace expanse::detail {
class Backend;
}

namespace expanse::detail::vk {

/// The process-wide context for device `index` (-1: best usable), created on first use and
/// kept: creating a device and compiling pipelines costs more than most triangulations.
std::shared_ptr<Context> shared_context(int index);

/// The Vulkan Backend on a context the caller made (a borrowed device, for interop).
std::unique_ptr<Backend> make_backend_on(std::shared_ptr<Context> context);

/// Runs shaders/predicate_test.comp. cases: 8 doubles per case (points a, b, c, d).
/// signs: 8 ints per case; eft: 4 doubles per case (see the shader).
void run_predicate_kernel(Context& context, std::span<const double> cases,
                          std::vector<std::int32_t>& signs, std::vector<double>& eft);

/// Start-up check that the device evaluates the error-free transformations exactly (no fma
/// contraction, correct rounding). Returns an empty string, or what went wrong.
std::string eft_self_test(Context& context);

}  // namespace expanse::detail::vk
