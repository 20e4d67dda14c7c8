#pragma once
// Peer triangulators, measured on the same points as Expanse. This header is free of Expanse
// types so the peers build and run on their own (expanse-bench-peers) while the engine changes.
#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace bench {

/// Same layout as expanse::Point2 (x then y, two doubles): peers read the caller's array in place.
struct XY {
  double x = 0.0;
  double y = 0.0;
};

/// One timed triangulation: named stages in order, their sum, and what came out.
struct PeerRun {
  std::vector<std::pair<std::string, double>> stages_ms;
  double total_ms = 0.0;
  std::size_t triangles = 0;
};

/// CGAL Delaunay_triangulation_2 with the Epick kernel; range insert (spatial sort inside), then
/// index triangles and neighbours are read out, so the work matches what Expanse returns.
PeerRun run_cgal(std::span<const XY> points);

/// Qhull (libqhull_r) as scipy.spatial.Delaunay drives it: "d Qbb Qc Qz Q12 Qt", then triangles
/// (made counter-clockwise) and neighbours read out of the lower facets.
PeerRun run_qhull(std::span<const XY> points);

/// delaunator (npm) in node: the points go through a binary file; the script does its own warm-up
/// and repetitions in one process and times only `new Delaunator(coords)` with process.hrtime.
struct ExternalRuns {
  std::vector<PeerRun> runs;
  std::string version;  ///< "delaunator X.Y.Z, node vA.B.C"
};
/// Returns nothing and sets why_not when node or the package is missing or the script fails.
std::optional<ExternalRuns> run_delaunator(std::span<const XY> points, int warmup, int repetitions,
                                           const std::string& script, std::string& why_not);

/// "CGAL 5.5.1", "Qhull 2020.2 ..." for the records.
std::string cgal_version();
std::string qhull_version();

}  // namespace bench
