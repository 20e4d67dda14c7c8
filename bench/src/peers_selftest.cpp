// expanse-bench-peers: the peers alone, on uniform points of its own, without the engine.
// It checks that the peer drivers build, run and agree on the triangle count; CI runs it so that
// a broken peer is found before a long benchmark run is.
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "peers.hpp"
#include "support.hpp"

#ifndef EXPANSE_BENCH_DELAUNATOR_SCRIPT
#define EXPANSE_BENCH_DELAUNATOR_SCRIPT ""
#endif

int main(int argc, char** argv) {
  const std::size_t n = argc > 1 ? bench::parse_count(argv[1]) : 100000;
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<bench::XY> points(n);
  for (auto& p : points) p = {unit(rng), unit(rng)};

  int failures = 0;
  std::size_t expected = 0;
  auto report = [&](const char* name, const bench::PeerRun& run) {
    std::printf("%-11s n=%zu  %9.2f ms  %zu triangles\n", name, n, run.total_ms, run.triangles);
    if (expected == 0) expected = run.triangles;
    if (run.triangles != expected || run.triangles == 0) {
      std::printf("  MISMATCH: expected %zu triangles\n", expected);
      ++failures;
    }
  };
  bench::run_cgal(points);  // warm-up: page in the allocator and the code
  report("cgal", bench::run_cgal(points));
  bench::run_qhull(points);
  report("qhull", bench::run_qhull(points));
  std::string why_not;
  if (auto runs = bench::run_delaunator(points, 1, 1, EXPANSE_BENCH_DELAUNATOR_SCRIPT, why_not)) {
    report("delaunator", runs->runs.front());
  } else {
    std::printf("delaunator skipped: %s\n", why_not.c_str());
  }
  std::printf("%s, %s\n", bench::cgal_version().c_str(), bench::qhull_version().c_str());
  return failures ? EXIT_FAILURE : EXIT_SUCCESS;
}
