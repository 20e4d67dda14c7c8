// CUDA backend benchmark: one JSON object per (distribution, n) on stdout.
//
//   expanse_bench_cuda [--sizes 512,1024,2048,4096] [--dists uniform,gaussian,grid,kuzmin]
//                      [--reps 5] [--no-pipeline] [--paper] [--sites-per-bucket X] [--scale F]
//
// --scale F multiplies every generated coordinate by F (rounded): the integer grid times 0.1 is
// a decimal grid, whose squares are cocircular up to rounding, not exactly (recorded as "scale").
//
// Sizes are sides: n = side^2 points. Times are medians after one warm-up run:
//   host_to_host_ms  expanse::triangulate(): std::vector points -> Mesh (triangles + neighbours)
//   host_to_host_reused_ms  the same into the previous repetition's Mesh (Triangulator::
//                    triangulate(points, mesh)): its storage filled again, no fresh pages
//                    (pipeline_device_stages_ms: its device stages, the device's own
//                    preparation of the sites among them)
//   host_to_host_host_prepare_ms  host_to_host_ms with the sites prepared on the host
//                    (EXPANSE_CUDA_PREPARE=host), as before the device prepared them
//   backend_ms       Backend::grow() alone: prepared sites -> triangles + neighbours in vectors
//   gpu_ms           device stages without transfers (CUDA events)
//
//   expanse_bench_cuda --transfers [--reps 5]
// instead times the transfers under a 4096^2 run, one JSON line each (median ms, GB/s): 805 MB
// device -> host straight into pinned memory (the bus alone), and through the backend's pinned
// staging into prefaulted pageable memory (32 MiB chunks and 8 copying threads, 64 MiB and 16);
// 268 MB host -> device the same ways; and pinning the pageable pages in place and releasing
// them (timed apart, in one piece and in 16), with a copy straight into them.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "backends/backend.hpp"
#include "cuda_internal.hpp"
#include "expanse/generate.hpp"
#include "expanse/triangulate.hpp"
#include "hull/convex_hull.hpp"
#include "input/parallel.hpp"
#include "input/site_set.hpp"

using namespace expanse;
using namespace expanse::detail;

namespace {

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream in(s);
  std::string item;
  while (std::getline(in, item, ',')) out.push_back(item);
  return out;
}

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

double now_ms() {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

/// The --transfers probe (see the top of this file).
int time_transfers(int reps) {
  constexpr std::size_t down_bytes = std::size_t{805} << 20, up_bytes = std::size_t{268} << 20;
  cudaStream_t stream;
  EXPANSE_CUDA(cudaStreamCreate(&stream));
  void* device = nullptr;
  void* pinned = nullptr;
  EXPANSE_CUDA(cudaMalloc(&device, down_bytes));
  EXPANSE_CUDA(cudaMemset(device, 1, down_bytes));
  EXPANSE_CUDA(cudaHostAlloc(&pinned, down_bytes, cudaHostAllocDefault));
  std::memset(pinned, 2, down_bytes);
  std::vector<unsigned char> pageable;
  pageable.reserve(down_bytes);
  prefault_capacity(pageable);
  pageable.resize(down_bytes);
  auto report = [&](const char* what, std::size_t bytes, auto&& run) {
    std::vector<double> ms;
    for (int r = 0; r <= reps; ++r) {
      EXPANSE_CUDA(cudaStreamSynchronize(stream));
      const double t0 = now_ms();
      run();
      EXPANSE_CUDA(cudaStreamSynchronize(stream));
      if (r > 0) ms.push_back(now_ms() - t0);
    }
    const double m = median(ms);
    std::printf("{\"transfer\": \"%s\", \"bytes\": %zu, \"median_ms\": %.3f, \"gb_per_s\": %.2f}\n", what, bytes, m,
                double(bytes) / 1e6 / m);
    std::fflush(stdout);
  };
  report("d2h pinned", down_bytes, [&] {
    EXPANSE_CUDA(cudaMemcpyAsync(pinned, device, down_bytes, cudaMemcpyDeviceToHost, stream));
  });
  report("h2d pinned", up_bytes, [&] {
    EXPANSE_CUDA(cudaMemcpyAsync(device, pinned, up_bytes, cudaMemcpyHostToDevice, stream));
  });
  for (const auto& [chunk, threads] : {std::pair{std::size_t{32} << 20, std::size_t{8}},
                                        std::pair{std::size_t{64} << 20, std::size_t{16}}}) {
    cuda::PinnedStaging staging(chunk, threads);
    const std::string suffix =
        " staged " + std::to_string(chunk >> 20) + " MiB, " + std::to_string(threads) + " threads";
    report(("d2h" + suffix).c_str(), down_bytes, [&] { staging.download(pageable.data(), device, down_bytes, stream); });
    report(("h2d" + suffix).c_str(), up_bytes, [&] { staging.upload(device, pageable.data(), up_bytes, stream); });
  }
  // The output's own pages pinned for the time of the copy: what pinning and releasing them
  // cost next to the copy it saves, apart (release is what a caller waits for after the copy),
  // in one call and in 2 MiB-aligned pieces on all threads.
  const auto pin_apart = [&](std::size_t pieces) {
    const std::size_t piece = ((down_bytes / pieces + (std::size_t{2} << 20) - 1) >> 21) << 21;
    const auto each = [&](auto&& call) {
      std::vector<std::thread> threads;
      for (std::size_t at = 0; at < down_bytes; at += piece)
        threads.emplace_back([&, at] { call(pageable.data() + at, std::min(piece, down_bytes - at)); });
      for (auto& t : threads) t.join();
    };
    std::vector<double> pin_ms, release_ms;
    for (int r = 0; r <= reps; ++r) {
      const double t0 = now_ms();
      each([](unsigned char* at, std::size_t bytes) { EXPANSE_CUDA(cudaHostRegister(at, bytes, cudaHostRegisterDefault)); });
      const double t1 = now_ms();
      each([](unsigned char* at, std::size_t) { EXPANSE_CUDA(cudaHostUnregister(at)); });
      const double t2 = now_ms();
      if (r > 0) {
        pin_ms.push_back(t1 - t0);
        release_ms.push_back(t2 - t1);
      }
    }
    for (const auto& [what, ms] : {std::pair{"pin", &pin_ms}, std::pair{"release", &release_ms}}) {
      std::printf("{\"transfer\": \"%s, %zu pieces\", \"bytes\": %zu, \"median_ms\": %.3f, \"gb_per_s\": %.2f}\n", what,
                  pieces, down_bytes, median(*ms), double(down_bytes) / 1e6 / median(*ms));
    }
    std::fflush(stdout);
  };
  pin_apart(1);
  pin_apart(16);
  EXPANSE_CUDA(cudaHostRegister(pageable.data(), down_bytes, cudaHostRegisterDefault));
  report("d2h registered", down_bytes, [&] {
    EXPANSE_CUDA(cudaMemcpyAsync(pageable.data(), device, down_bytes, cudaMemcpyDeviceToHost, stream));
  });
  EXPANSE_CUDA(cudaHostUnregister(pageable.data()));
  EXPANSE_CUDA(cudaFreeHost(pinned));
  EXPANSE_CUDA(cudaFree(device));
  EXPANSE_CUDA(cudaStreamDestroy(stream));
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> sizes{"512", "1024", "2048", "4096"};
  std::vector<std::string> dists{"uniform", "gaussian", "grid", "kuzmin"};
  int reps = 5;
  bool pipeline = true;
  bool paper = false;
  bool transfers = false;
  double sites_per_bucket = 0.0;  // 0: the layout's default
  double scale = 1.0;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--sizes" && i + 1 < argc) sizes = split(argv[++i]);
    else if (a == "--dists" && i + 1 < argc) dists = split(argv[++i]);
    else if (a == "--reps" && i + 1 < argc) reps = std::max(1, std::atoi(argv[++i]));
    else if (a == "--no-pipeline") pipeline = false;
    else if (a == "--paper") paper = true;
    else if (a == "--transfers") transfers = true;
    else if (a == "--sites-per-bucket" && i + 1 < argc) sites_per_bucket = std::atof(argv[++i]);
    else if (a == "--scale" && i + 1 < argc) scale = std::atof(argv[++i]);
    else {
      std::fprintf(stderr,
                   "usage: %s [--sizes 512,1024] [--dists uniform,grid] [--reps N] [--no-pipeline] [--paper] "
                   "[--sites-per-bucket X] [--scale F] | --transfers\n",
                   argv[0]);
      return 2;
    }
  }
  std::unique_ptr<Backend> backend;
  try {
    backend = make_cuda_backend(-1);
  } catch (const Error& e) {
    std::fprintf(stderr, "no CUDA backend: %s\n", e.what());
    return 77;
  }
  if (transfers) return time_transfers(reps);
  Layout layout = paper ? Layout::paper() : Layout{};
  if (sites_per_bucket > 0.0) layout.sites_per_bucket = sites_per_bucket;
  for (const auto& dist : dists) {
    for (const auto& side_text : sizes) {
      const std::size_t side = std::stoul(side_text);
      const std::size_t n = side * side;
      std::vector<Point2> points = generate_points(dist, n, 42);
      if (scale != 1.0)
        for (Point2& p : points) p = {p.x * scale, p.y * scale};
      const double t0 = now_ms();
      SiteSet sites = prepare_sites(points);
      const double t1 = now_ms();
      Hull hull = convex_hull(sites);
      const double t2 = now_ms();
      std::vector<double> backend_ms, gpu_ms, h2h_ms, h2h_reused_ms, h2h_host_prepare_ms, seam_share;
      std::map<std::string, std::vector<double>> stage_ms, host_stage_ms, pipeline_stage_ms, pipeline_device_stage_ms;
      cuda::RunCounters counters;
      std::size_t deferred = 0, triangles = 0;
      bool short_sort = false;  // the pipeline's preparation on the device sorted by short keys
      std::string error;
      try {
        for (int r = 0; r <= reps; ++r) {  // r == 0: warm-up
          const double g0 = now_ms();
          GrowResult result = backend->grow(GrowInput{sites, hull, layout});
          const double g1 = now_ms();
          if (r == 0) continue;
          backend_ms.push_back(g1 - g0);
          double gpu = 0.0;
          for (const auto& s : result.device_stages) {
            stage_ms[s.name].push_back(s.ms);
            if (s.name != "upload" && s.name != "download") gpu += s.ms;
          }
          for (const auto& s : result.host_stages) host_stage_ms[s.name].push_back(s.ms);
          gpu_ms.push_back(gpu);
          deferred = result.partial.deferred_expansions;
          triangles = result.partial.triangles.size();
          counters = cuda::last_run_counters();
        }
        if (pipeline) {
          Options options;
          options.backend = BackendKind::cuda;
          options.layout = layout;
          // One Triangulator for every repetition, as an application would keep it: the
          // backend's stream, pinned staging and memory pool are made once, not timed.
          Triangulator triangulator(options);
          for (int r = 0; r <= reps; ++r) {
            const double p0 = now_ms();
            Mesh mesh = triangulator.triangulate(points);
            const double p1 = now_ms();
            short_sort = cuda::last_run_counters().short_morton_sort;
            if (r == 0) continue;
            h2h_ms.push_back(p1 - p0);
            seam_share.push_back(mesh.triangles.empty() ? 0.0
                                                        : static_cast<double>(mesh.stats.seam_triangles) /
                                                              static_cast<double>(mesh.triangles.size()));
            for (const auto& s : mesh.stats.stages) pipeline_stage_ms[s.name].push_back(s.ms);
          }
          Mesh kept;
          for (int r = 0; r <= reps; ++r) {
            const double p0 = now_ms();
            triangulator.triangulate(points, kept);
            const double p1 = now_ms();
            if (r > 0) h2h_reused_ms.push_back(p1 - p0);
            for (const auto& s : kept.stats.device_stages)
              if (r > 0) pipeline_device_stage_ms[s.name].push_back(s.ms);
          }
          // The same with the sites prepared on the host (prepare_sites), as before the device
          // did it: the comparison in one run.
          setenv("EXPANSE_CUDA_PREPARE", "host", 1);
          for (int r = 0; r <= reps; ++r) {
            const double p0 = now_ms();
            Mesh mesh = triangulator.triangulate(points);
            const double p1 = now_ms();
            if (r > 0) h2h_host_prepare_ms.push_back(p1 - p0);
          }
          unsetenv("EXPANSE_CUDA_PREPARE");
        }
      } catch (const Error& e) {
        error = std::string(to_string(e.code())) + ": " + e.what();
      }
      std::printf("{\"device\":\"%s\",\"layout\":\"%s\",\"sites_per_bucket\":%g,\"distribution\":\"%s\",\"side\":%zu,"
                  "\"n\":%zu,\"sites\":%zu,\"hull\":%zu,\"reps\":%d,",
                  backend->device_name().c_str(), paper ? "paper" : "per_site", layout.sites_per_bucket, dist.c_str(),
                  side, n, sites.points.size(), hull.sites.size(), reps);
      if (scale != 1.0) std::printf("\"scale\":%g,", scale);
      if (!error.empty()) {
        std::string escaped;
        for (char c : error) escaped += (c == '"' || c == '\\') ? ' ' : c;
        std::printf("\"error\":\"%s\"}\n", escaped.c_str());
        std::fflush(stdout);
        continue;
      }
      std::printf("\"prepare_sites_ms\":%.3f,\"hull_ms\":%.3f,\"backend_ms\":%.3f,\"gpu_ms\":%.3f,", t1 - t0, t2 - t1,
                  median(backend_ms), median(gpu_ms));
      if (pipeline)
        std::printf("\"host_to_host_ms\":%.3f,\"host_to_host_reused_ms\":%.3f,\"host_to_host_host_prepare_ms\":%.3f,"
                    "\"seam_share\":%.6g,",
                    median(h2h_ms), median(h2h_reused_ms), median(h2h_host_prepare_ms), median(seam_share));
      std::printf("\"triangles\":%zu,\"deferred\":%zu,\"predicates\":%llu,\"bytes_to_device\":%llu,\"bytes_to_host\":%llu,\"max_cells_per_site\":%llu,\"sites_over_4096_cells\":%llu,\"sites_over_budget\":%llu,\"uniform_cells\":%s,\"short_morton_sort\":%s,",
                  triangles, deferred, static_cast<unsigned long long>(counters.predicates),
                  static_cast<unsigned long long>(counters.bytes_to_device),
                  static_cast<unsigned long long>(counters.bytes_to_host),
                  static_cast<unsigned long long>(counters.max_cells_per_site),
                  static_cast<unsigned long long>(counters.sites_over_4096_cells),
                  static_cast<unsigned long long>(counters.sites_over_budget),
                  counters.uniform_cells ? "true" : "false", short_sort ? "true" : "false");
      auto dump = [](const char* key, const std::map<std::string, std::vector<double>>& m, bool comma) {
        std::printf("\"%s\":{", key);
        bool first = true;
        for (const auto& [name, v] : m) {
          std::printf("%s\"%s\":%.3f", first ? "" : ",", name.c_str(), median(v));
          first = false;
        }
        std::printf("}%s", comma ? "," : "");
      };
      dump("device_stages_ms", stage_ms, true);
      dump("backend_host_stages_ms", host_stage_ms, pipeline);
      if (pipeline) {
        dump("pipeline_stages_ms", pipeline_stage_ms, true);
        dump("pipeline_device_stages_ms", pipeline_device_stage_ms, false);
      }
      std::printf("}\n");
      std::fflush(stdout);
    }
  }
  return 0;
}
