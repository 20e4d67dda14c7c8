#pragma once
// The Vulkan backend's internals that tests reach into (the Backend itself is created through
// make_vulkan_backend in backends/backend.hpp).
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "backends/vulkan/vk_context.hpp"
#include "expanse/types.hpp"
#include "hull/convex_hull.hpp"
#include "input/site_set.hpp"
#include "backends/partial_triangulation.hpp"

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
/// signs: PREDICATE_TEST_SIGNS ints per case; eft: PREDICATE_TEST_EFT doubles per case
/// (host_device.h, and the shader).
void run_predicate_kernel(Context& context, std::span<const double> cases,
                          std::vector<std::int32_t>& signs, std::vector<double>& eft);

/// The per-site layout's bucketing on the device alone (shaders/bucket.comp, scan.comp): the
/// sites sorted into a cells x cells grid over their bounding box, for tests to compare with
/// the host's counting sort. crowded: a cell held too many sites to rank (results then void).
struct DeviceBuckets {
  std::vector<Point2> sites;              // sorted by cell, row-major; SiteSet order within a cell
  std::vector<std::int32_t> cell_start;   // cells^2 + 1
  std::vector<std::int32_t> to_site;      // sorted id -> SiteSet id
  std::vector<std::int32_t> predecessor;  // hull predecessors in sorted ids
  bool crowded = false;
};
DeviceBuckets bucket_on_device(Context& context, const SiteSet& sites, const Hull& hull, int cells);

/// The per-site layout's device audit on its own: shaders/audit.comp over `partial` (SiteSet
/// ids, with neighbours) and the host's check of the open edges it lists. True when both pass,
/// i.e. when the pipeline may skip its host audit (seam/adjacency_audit.cpp's checks).
bool audit_on_device(Context& context, const PartialTriangulation& partial, const Hull& hull);

/// Start-up check that the device evaluates the error-free transformations exactly (no fma
/// contraction, correct rounding). Returns an empty string, or what went wrong.
std::string eft_self_test(Context& context);

}  // namespace expanse::detail::vk
