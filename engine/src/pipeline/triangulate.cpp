#include "expanse/triangulate.hpp"

#include <future>
#include <optional>
#include <type_traits>

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
#include "support/timing.hpp"

namespace expanse {

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

namespace detail {
namespace {

// One run of the pipeline, step by step: prepare the sites (on the device where the backend
// offers it, else here), grow the front, audit the device's adjacency, complete the seam,
// output in input indices.
class PipelineRun {
  // The device's first triangles turned into input indices during the seam's growth.
  struct EarlyOutput {
    std::size_t remapped = 0;  // triangles [0, remapped) are done once `job` is
    double ms = 0.0;
    std::future<void> job;
  };

 public:
  PipelineRun(Backend& backend, const Options& options, std::span<const Point2> points, Mesh& mesh)
      : backend_(backend), options_(options), points_(points), mesh_(mesh) {
    stats_.backend = std::string(to_string(backend.kind()));
    stats_.device = backend.device_name();
    stats_.input_points = points.size();
  }

  void run() {
    if (points_.size() >= 3 && backend_.prepares_sites(options_.layout)) prepare_on_device();
    if (!sites_) prepare_on_host();
    stats_.sites = sites_->points.size();
    stats_.duplicates = stats_.input_points - stats_.sites;
    stats_.hull_sites = hull_->sites.size();
    accept();
    if (sites_->size() >= 3 && !hull_->collinear) grow_and_complete();
    stats_.triangles = mesh_.triangles.size();
    mesh_.hull = to_input_indices(hull_->sites, *sites_);
    mesh_.representative = std::move(sites_->representative);  // the last use of the sites
    stats_.total_ms = run_time_.ms();
    mesh_.stats = std::move(stats_);
  }

 private:
  // The input is accepted once it is validated: from then on `mesh` is rewritten, the storage
  // of its two large vectors handed to the backend to fill again (allocate_full_triangulation
  // empties them). Emptied first, so that an error leaves no stale part.
  void accept() {
    if (accepted_) return;
    accepted_ = true;
    recycled_.triangles.swap(mesh_.triangles);
    recycled_.neighbors.swap(mesh_.neighbors);
    mesh_.hull.clear();
    mesh_.representative.clear();
    mesh_.stats = Stats{};
  }

  // The device sorts and merges: the host validates, and finds the hull on the raw points on
  // another thread while the device uploads and sorts them (it needs the hull after that).
  void prepare_on_device() {
    const InputScan scan = timed("prepare (scan)", [&] { return scan_input(points_); });
    accept();
    double hull_ms = 0.0;
    std::future<InputHull> hull_job = std::async(std::launch::async, [&] {
      const Stopwatch hull_time;
      InputHull found = convex_hull_of_input(points_, scan);
      hull_ms = hull_time.ms();
      return found;
    });
    std::optional<InputHull> input_hull;
    const auto hull_sites = [&]() -> const std::vector<std::int32_t>* {
      if (!input_hull) input_hull.emplace(hull_job.get());
      return !input_hull->collinear && input_hull->sites.size() >= 3 ? &input_hull->sites : nullptr;
    };
    std::optional<InputGrowResult> made = timed("grow", [&] {
      return backend_.grow_from_input({points_, scan, hull_sites, options_.layout, &recycled_});
    });
    if (hull_job.valid()) hull_job.wait();  // declined before it needed the hull
    stats_.stages.push_back({"hull (input, while the device prepares)", hull_ms});
    if (made) {
      sites_.emplace(std::move(made->sites));
      hull_.emplace(std::move(made->hull));
      grown_on_device_.emplace(std::move(made->grown));
    }
  }

  void prepare_on_host() {
    sites_.emplace(timed("prepare", [&] { return prepare_sites(points_); }));
    hull_.emplace(timed("hull", [&] { return convex_hull(*sites_); }));
  }

  void grow_and_complete() {
    GrowResult grown = grown_on_device_ ? std::move(*grown_on_device_) : timed("grow", [&] {
      return backend_.grow({*sites_, *hull_, options_.layout, &recycled_});
    });
    for (auto& stage : grown.host_stages) stats_.stages.push_back(std::move(stage));
    stats_.device_stages = std::move(grown.device_stages);
    stats_.iterations = grown.iterations;
    stats_.deferred_expansions = grown.partial.deferred_expansions;
    stats_.gpu_triangles = grown.partial.triangles.size();

    PartialTriangulation& partial = grown.partial;
    // Device adjacency is used only if it passes the audit; otherwise it is derived here.
    if (!partial.neighbors.empty() && !grown.adjacency_audited) {
      const bool trusted = timed("audit", [&] { return adjacency_is_trustworthy(partial, *hull_); });
      if (!trusted) partial.neighbors.clear();
    }
    // Declared after `grown`, so that it is destroyed first: its job reads grown's triangles.
    EarlyOutput early;
    const std::size_t expected = 2 * static_cast<std::size_t>(sites_->size()) - hull_->sites.size() - 2;
    if (partial.triangles.size() != expected) {
      complete(partial, expected - partial.triangles.size(), early);
    } else if (options_.neighbors && partial.neighbors.size() != partial.triangles.size()) {
      partial.neighbors = timed("neighbors", [&] { return derive_neighbors(partial.triangles); });
    }
    output(partial, early);
    // What the backend still does with the output's memory (releasing pinned pages) ends
    // before the output is handed over.
    if (grown.background.valid()) timed("backend (after the output)", [&] { grown.background.get(); });
  }

  // Something is left open: the seam stage searches a bucket tree over every site (built on
  // demand where its searches go when the seam is tiny next to the sites). The device's
  // triangles are turned into input indices on other threads while the seam grows on this one
  // (they are 99.99% of the output; the seam's growth is sequential).
  void complete(PartialTriangulation& partial, std::size_t missing, EarlyOutput& early) {
    const BucketTree tree = timed("buckets", [&] { return BucketTree::for_seam(*sites_, missing); });
    const auto remap_early = [&] {
      early.remapped = partial.triangles.size();
      early.job = std::async(std::launch::async, [&, device_made = std::span(partial.triangles.data(), early.remapped)] {
        const Stopwatch output_time;
        remap_to_input(device_made, *sites_);
        early.ms = output_time.ms();
      });
    };
    const SeamStats seam = timed("seam", [&] { return complete_seam(*sites_, *hull_, tree, partial, remap_early); });
    stats_.seam_triangles = seam.triangles_made;
    stats_.stages.push_back({"seam: setup", seam.setup_ms});
    stats_.stages.push_back({"seam: open edges", seam.open_ms});
    stats_.stages.push_back({"seam: growth", seam.grow_ms});
  }

  void output(PartialTriangulation& partial, EarlyOutput& early) {
    timed("output", [&] {
      if (early.job.valid()) early.job.get();
      mesh_.triangles = std::move(partial.triangles);
      remap_to_input(std::span(mesh_.triangles).subspan(early.remapped), *sites_);
      if (options_.neighbors) mesh_.neighbors = std::move(partial.neighbors);
    });
    if (early.remapped > 0) stats_.stages.push_back({"output: the device's triangles (during the seam)", early.ms});
  }

  // Runs one named stage and records its wall time.
  template <class Work>
  std::invoke_result_t<Work&> timed(const char* name, Work&& work) {
    const Stopwatch stage_time;
    if constexpr (std::is_void_v<decltype(work())>) {
      work();
      stats_.stages.push_back({name, stage_time.ms()});
    } else {
      auto result = work();
      stats_.stages.push_back({name, stage_time.ms()});
      return result;
    }
  }

  Backend& backend_;
  const Options& options_;
  std::span<const Point2> points_;
  Mesh& mesh_;
  const Stopwatch run_time_;
  Stats stats_;
  PartialTriangulation recycled_;
  bool accepted_ = false;
  std::optional<SiteSet> sites_;
  std::optional<Hull> hull_;
  std::optional<GrowResult> grown_on_device_;
};

}  // namespace

void run_pipeline(Backend& backend, const Options& options, std::span<const Point2> points, Mesh& mesh) {
  PipelineRun(backend, options, points, mesh).run();
}

}  // namespace detail

Mesh triangulate(std::span<const Point2> points, const Options& options) {
  return Triangulator(options).triangulate(points);
}

}  // namespace expanse
