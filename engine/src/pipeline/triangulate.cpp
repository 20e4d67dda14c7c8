#include "expanse/triangulate.hpp"

#include <chrono>
#include <future>
#include <optional>

#include "grid/bucket_tree.hpp"
#include "hull/convex_hull.hpp"
#include "input/site_set.hpp"
#include "predicates/predicates.hpp"
#include "expanse/error.hpp"
#include "pipeline/backend_registry.hpp"
#include "pipeline/output.hpp"
#include "pipeline/run_pipeline.hpp"
#include "seam/adjacency_audit.hpp"
#include "seam/seam_completion.hpp"

namespace expanse {
namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// Runs one named stage and records its wall time.
template <class Work>
auto timed(Stats& stats, const char* name, Work&& work) {
  const auto start = Clock::now();
  if constexpr (std::is_void_v<decltype(work())>) {
    work();
    stats.stages.push_back({name, ms_since(start)});
  } else {
    auto result = work();
    stats.stages.push_back({name, ms_since(start)});
    return result;
  }
}

}  // namespace

struct Triangulator::Impl {
  Options options;
  std::unique_ptr<detail::Backend> backend;
};

namespace detail {

void require_exact_arithmetic() {
  // Exactness rests on error-free transformations; a build that fused them into FMA, or a CPU
  // flushing subnormals, must not return meshes. Checked once per process.
  static const bool arithmetic_is_exact = detail::predicates_self_test();
  if (!arithmetic_is_exact) {
    throw Error(ErrorCode::internal,
                "the exact-arithmetic self-test failed: this build contracts floating-point operations "
                "(FMA) or flushes subnormals; rebuild with -ffp-contract=off");
  }
}

}  // namespace detail

Triangulator::Triangulator(const Options& options) : impl_(std::make_unique<Impl>()) {
  detail::require_exact_arithmetic();
  impl_->options = options;
  impl_->backend = detail::make_backend(options.backend, options.device);
}
Triangulator::~Triangulator() = default;
Triangulator::Triangulator(Triangulator&&) noexcept = default;
Triangulator& Triangulator::operator=(Triangulator&&) noexcept = default;

BackendKind Triangulator::backend() const { return impl_->backend->kind(); }

Mesh Triangulator::triangulate(std::span<const Point2> points) {
  return detail::run_pipeline(*impl_->backend, impl_->options, points);
}

void Triangulator::triangulate(std::span<const Point2> points, Mesh& mesh) {
  detail::run_pipeline(*impl_->backend, impl_->options, points, mesh);
}

Mesh detail::run_pipeline(Backend& backend, const Options& options, std::span<const Point2> points) {
  Mesh mesh;
  run_pipeline(backend, options, points, mesh);
  return mesh;
}

void detail::run_pipeline(Backend& backend, const Options& options, std::span<const Point2> points, Mesh& mesh) {
  const auto start = Clock::now();
  Stats stats;
  stats.backend = std::string(to_string(backend.kind()));
  stats.device = backend.device_name();
  stats.input_points = points.size();

  // The input is accepted once it is validated: from then on `mesh` is rewritten, the storage of
  // its two large vectors handed to the backend to fill again (allocate_full_triangulation
  // empties them). Emptied first, so that an error leaves no stale part.
  detail::PartialTriangulation recycled;
  bool accepted = false;
  const auto accept = [&] {
    if (accepted) return;
    accepted = true;
    recycled.triangles.swap(mesh.triangles);
    recycled.neighbors.swap(mesh.neighbors);
    mesh.hull.clear();
    mesh.representative.clear();
    mesh.stats = Stats{};
  };

  std::optional<detail::SiteSet> prepared;
  std::optional<detail::Hull> prepared_hull;
  std::optional<detail::GrowResult> grown_on_device;
  if (points.size() >= 3 && backend.prepares_sites(options.layout)) {
    // The device sorts and merges: the host validates, and finds the hull on the raw points on
    // another thread while the device uploads and sorts them (it needs the hull after that).
    const detail::InputScan scan = timed(stats, "prepare (scan)", [&] { return detail::scan_input(points); });
    accept();
    double hull_ms = 0.0;
    std::future<detail::InputHull> hull_job = std::async(std::launch::async, [&] {
      const auto hull_start = Clock::now();
      detail::InputHull found = detail::convex_hull_of_input(points, scan);
      hull_ms = ms_since(hull_start);
      return found;
    });
    std::optional<detail::InputHull> input_hull;
    const auto hull_sites = [&]() -> const std::vector<std::int32_t>* {
      if (!input_hull) input_hull.emplace(hull_job.get());
      return !input_hull->collinear && input_hull->sites.size() >= 3 ? &input_hull->sites : nullptr;
    };
    std::optional<detail::InputGrowResult> made = timed(stats, "grow", [&] {
      return backend.grow_from_input({points, scan, hull_sites, options.layout, &recycled});
    });
    if (hull_job.valid()) hull_job.wait();  // declined before it needed the hull
    stats.stages.push_back({"hull (input, while the device prepares)", hull_ms});
    if (made) {
      prepared.emplace(std::move(made->sites));
      prepared_hull.emplace(std::move(made->hull));
      grown_on_device.emplace(std::move(made->grown));
    }
  }
  if (!prepared) {
    prepared.emplace(timed(stats, "prepare", [&] { return detail::prepare_sites(points); }));
    prepared_hull.emplace(timed(stats, "hull", [&] { return detail::convex_hull(*prepared); }));
  }
  detail::SiteSet& sites = *prepared;
  const detail::Hull& hull = *prepared_hull;
  stats.sites = sites.points.size();
  stats.duplicates = stats.input_points - stats.sites;
  stats.hull_sites = hull.sites.size();
  accept();

  if (sites.size() >= 3 && !hull.collinear) {
    detail::GrowResult grown = grown_on_device ? std::move(*grown_on_device) : timed(stats, "grow", [&] {
      return backend.grow({sites, hull, options.layout, &recycled});
    });
    for (auto& stage : grown.host_stages) stats.stages.push_back(std::move(stage));
    stats.device_stages = std::move(grown.device_stages);
    stats.iterations = grown.iterations;
    stats.deferred_expansions = grown.partial.deferred_expansions;
    stats.gpu_triangles = grown.partial.triangles.size();

    detail::PartialTriangulation& partial = grown.partial;
    const std::size_t expected = 2 * static_cast<std::size_t>(sites.size()) - hull.sites.size() - 2;
    // Device adjacency is used only if it passes the audit; otherwise it is derived here.
    if (!partial.neighbors.empty() && !grown.adjacency_audited) {
      const bool trusted = timed(stats, "audit", [&] { return detail::adjacency_is_trustworthy(partial, hull); });
      if (!trusted) partial.neighbors.clear();
    }
    // The device's triangles in input indices, made on other threads while the seam grows on
    // this one (they are 99.99% of the output; the seam's growth is sequential).
    std::size_t remapped = 0;
    double early_output_ms = 0.0;
    std::future<void> early_output;
    if (partial.triangles.size() != expected) {
      // Something is left open: the seam stage searches a bucket tree over every site (built on
      // demand where its searches go when the seam is tiny next to the sites).
      const std::size_t missing = expected - partial.triangles.size();
      const detail::BucketTree tree = timed(stats, "buckets", [&] { return detail::BucketTree::for_seam(sites, missing); });
      const auto remap_early = [&] {
        remapped = partial.triangles.size();
        early_output = std::async(std::launch::async, [&, device_made = std::span(partial.triangles.data(), remapped)] {
          const auto begin = Clock::now();
          detail::remap_to_input(device_made, sites);
          early_output_ms = ms_since(begin);
        });
      };
      const detail::SeamStats seam =
          timed(stats, "seam", [&] { return detail::complete_seam(sites, hull, tree, partial, remap_early); });
      stats.seam_triangles = seam.triangles_made;
      stats.stages.push_back({"seam: setup", seam.setup_ms});
      stats.stages.push_back({"seam: open edges", seam.open_ms});
      stats.stages.push_back({"seam: growth", seam.grow_ms});
    } else if (options.neighbors && partial.neighbors.size() != partial.triangles.size()) {
      partial.neighbors = timed(stats, "neighbors", [&] { return detail::derive_neighbors(partial.triangles); });
    }

    timed(stats, "output", [&] {
      if (early_output.valid()) early_output.get();
      mesh.triangles = std::move(partial.triangles);
      detail::remap_to_input(std::span(mesh.triangles).subspan(remapped), sites);
      if (options.neighbors) mesh.neighbors = std::move(partial.neighbors);
    });
    if (remapped > 0) stats.stages.push_back({"output: the device's triangles (during the seam)", early_output_ms});
    // What the backend still does with the output's memory (releasing pinned pages) ends
    // before the output is handed over.
    if (grown.background.valid()) timed(stats, "backend (after the output)", [&] { grown.background.get(); });
  }
  stats.triangles = mesh.triangles.size();
  mesh.hull = detail::to_input_indices(hull.sites, sites);
  mesh.representative = std::move(sites.representative);  // the last use of sites
  stats.total_ms = ms_since(start);
  mesh.stats = std::move(stats);
}

Mesh triangulate(std::span<const Point2> points, const Options& options) {
  return Triangulator(options).triangulate(points);
}

}  // namespace expanse
