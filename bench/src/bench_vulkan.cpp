// expanse_vulkan_bench N [uniform|gaussian] [per-site|paper|cpu] [repeats]
//                      [blocks_per_side] [threads_per_block] [buckets_per_block_side]
// One JSON object per run on stdout: sizes, backend/device, total and per-stage times, GPU vs
// seam triangles, deferred expansions, iterations. The first run also pays device start-up and
// pipeline compilation, so repeats > 1 reports the later runs.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "expanse/error.hpp"
#include "expanse/triangulate.hpp"

int main(int argc, char** argv) {
  using namespace expanse;
  const std::size_t n = argc > 1 ? std::strtoull(argv[1], nullptr, 10) : 1000000;
  const std::string dist = argc > 2 ? argv[2] : "uniform";
  const std::string layout = argc > 3 ? argv[3] : "per-site";
  const int repeats = argc > 4 ? std::atoi(argv[4]) : 2;
  std::mt19937_64 rng(12345);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<Point2> points(n);
  for (auto& p : points) p = dist == "gaussian" ? Point2{normal(rng), normal(rng)} : Point2{unit(rng), unit(rng)};
  Options options;
  options.backend = layout == "cpu" ? BackendKind::cpu : BackendKind::vulkan;
  if (layout == "paper") options.layout = Layout::paper();
  if (argc > 5) options.layout.blocks_per_side = std::atoi(argv[5]);
  if (argc > 6) options.layout.threads_per_block = std::atoi(argv[6]);
  if (argc > 7) options.layout.buckets_per_block_side = std::atoi(argv[7]);
  options.neighbors = false;
  for (int run = 0; run < repeats; ++run) {
    try {
      const auto start = std::chrono::steady_clock::now();
      const Mesh mesh = triangulate(points, options);
      const double wall =
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
      const Stats& s = mesh.stats;
      std::printf("{\"n\": %zu, \"distribution\": \"%s\", \"layout\": \"%s\", \"blocks\": %d, \"threads\": %d, \"buckets\": %d, \"run\": %d, "
                  "\"backend\": \"%s\", \"device\": \"%s\", \"wall_ms\": %.3f, \"total_ms\": %.3f, "
                  "\"triangles\": %zu, \"gpu_triangles\": %zu, \"seam_triangles\": %zu, "
                  "\"seam_share\": %.6f, \"deferred\": %zu, \"iterations\": %zu, \"stages\": {",
                  n, dist.c_str(), layout.c_str(), options.layout.blocks_per_side,
                  options.layout.threads_per_block, options.layout.buckets_per_block_side, run,
                  s.backend.c_str(), s.device.c_str(), wall,
                  s.total_ms, s.triangles, s.gpu_triangles, s.seam_triangles,
                  s.triangles ? double(s.seam_triangles) / double(s.triangles) : 0.0,
                  s.deferred_expansions, s.iterations);
      for (std::size_t i = 0; i < s.stages.size(); ++i)
        std::printf("%s\"%s\": %.3f", i ? ", " : "", s.stages[i].name.c_str(), s.stages[i].ms);
      std::printf("}, \"device_stages\": {");
      for (std::size_t i = 0; i < s.device_stages.size(); ++i)
        std::printf("%s\"%s\": %.3f", i ? ", " : "", s.device_stages[i].name.c_str(),
                    s.device_stages[i].ms);
      std::printf("}}\n");
      std::fflush(stdout);
    } catch (const Error& e) {
      std::printf("{\"n\": %zu, \"layout\": \"%s\", \"error\": \"%s\", \"code\": \"%s\"}\n", n,
                  layout.c_str(), e.what(), to_string(e.code()));
      return e.code() == ErrorCode::backend_unavailable ? 77 : 1;
    }
  }
  return 0;
}
