#pragma once
// The CUDA backend's knobs: one struct, read from the environment in one function
// (tuning_from_environment, the backend's only getenv). docs/tuning.md ("CUDA backend") lists
// each knob, its default, what it trades and the measurement behind the default. A knob changes
// speed or memory, never the triangulation. Plain C++: the host tests build the star layout with
// a Tuning of their own, with or without nvcc.
#include <cstddef>
#include <optional>

#include "grid/quantile_tails.hpp"

namespace expanse::detail::cuda {

/// Blocks of 128 threads a multiprocessor that the star kernels' registers allow (4, 6 or 8): the
/// first phase's (and the main stream's lists of sites to walk again), the second phase's, and
/// the edge stream's (EdgeCells).
struct StarBlocks {
  int first = 8, later = 8, edge = 8;
};

/// A switch that the backend sets by the input unless forced.
enum class Forced { automatic, on, off };

struct Tuning {
  /// EXPANSE_CUDA_BUDGET: work units (cells or row segments, plus sites) a site's walk may take
  /// before it defers to the seam stage. Unset: box_search_budget.
  std::optional<unsigned> budget;
  /// EXPANSE_CUDA_FIRST_BUDGET: the first pass's budget (first_pass_budget when unset; 0: one
  /// pass with the whole budget). Tests force both passes' paths with it.
  std::optional<unsigned> first_budget;
  /// EXPANSE_CUDA_RETRY_BUDGET: the interior sites' retry budget (interior_retry_budget when
  /// unset). Tests make the retry defer with it.
  std::optional<unsigned> retry_budget;
  /// EXPANSE_CUDA_BLOCKS_PER_SM ("B" or "F,L,E"): the star kernels' register caps
  /// (default_star_blocks when unset); 4, 6 or 8 are compiled, other values round to them.
  std::optional<StarBlocks> blocks_per_sm;
  /// EXPANSE_CUDA_PHASES (1 or 2): walk the stars in one phase or two (two above 2^18 sites when
  /// unset). Tests force two phases on small inputs.
  std::optional<int> phases;
  /// EXPANSE_CUDA_STRIPS (0 or 1): the boundary strips off, or on at any size (automatic: from
  /// 2^16 sites on grids of equal cells). Tests force them onto small inputs.
  Forced strips = Forced::automatic;
  /// EXPANSE_CUDA_TAIL_COLUMNS (0 or 1): TailColumns off, or on for any quantile cells with
  /// guides (automatic: where the x-axis' tails are heavy). Tests force both.
  Forced tail_columns = Forced::automatic;
  /// EXPANSE_CUDA_TAILS ("0": plain quantiles; "share,factor"): how quantile cells weigh heavy
  /// tails (grid/quantile_tails.hpp).
  TailWeighing tails{};
  /// EXPANSE_CUDA_GRID (uniform or quantile): the bucket grid (automatic: uniform cells where a
  /// sample of the sites is spread evenly, quantile cells otherwise).
  enum class Grid { automatic, uniform, quantile } grid = Grid::automatic;
  /// EXPANSE_CUDA_AUDIT_ROOM: open edges the device audit lists in its first pass; more are
  /// listed by a second audit with room for all. Tests take the second audit with a small room.
  std::size_t audit_room = std::size_t{1} << 18;
  /// EXPANSE_CUDA_EDGE_RETRY ("edge" or "low:B"): where the edge sites' retry runs (automatic:
  /// on the low-priority stream with 2 blocks a multiprocessor, except for lattices). Tests force
  /// both launches.
  enum class EdgeRetry { automatic, edge, low } edge_retry = EdgeRetry::automatic;
  int edge_retry_blocks_per_sm = 2;  ///< with EdgeRetry::low or automatic
  /// EXPANSE_CUDA_MORTON_SORT (full or short): the device preparation's sort (automatic: the
  /// short sort where a sample forecasts few shared keys). Tests force both.
  enum class MortonSort { forecast, full, short_keys } morton_sort = MortonSort::forecast;
  /// EXPANSE_CUDA_PREPARE=host: the sites prepared on the host, not on the device.
  bool prepare_on_device = true;
  /// EXPANSE_CUDA_PIN_OUTPUT=1: pin the output vectors in place while the device works.
  bool pin_output = false;
  /// EXPANSE_CUDA_STAR_TIMELINE=1: print the star stage's timeline and list lengths to stderr.
  bool star_timeline = false;
};

/// The knobs set in the environment; every other field keeps its default.
Tuning tuning_from_environment();

/// The first pass's work budget (docs/tuning.md: what the retry leaves, warps walk 32 candidates
/// at a time, so the smaller the better while the retry stays short; small inputs fill few waves,
/// and their kernel is the tail of their heaviest sites; quantile cells above 2^20 sites stretch
/// kuzmin's searches a little past 2^10).
inline unsigned first_pass_budget(std::size_t sites, bool quantile_cells) {
  if (sites <= (std::size_t{1} << 18)) return 1u << 8;
  if (!quantile_cells || sites <= (std::size_t{1} << 20)) return 1u << 10;
  return 1u << 11;
}

/// The whole walk's budget for box scans: default_budget (2^16) above 2^20 sites; up to there
/// 2^13, the kernel being the tail of its few hull-hugging sites, whose triangles the seam stage
/// makes for less.
inline unsigned box_search_budget(std::size_t sites, unsigned default_budget) {
  return sites <= (std::size_t{1} << 20) ? 1u << 13 : default_budget;
}

/// The retry's budget for the sites away from the grid's edge (the edge's retry keeps the whole
/// budget): such a site runs long only in a sparse stretch of a clustered input, and a lone warp
/// walking it for 2^16 units held the stage after everything else was done.
inline unsigned interior_retry_budget(unsigned budget) { return budget < (1u << 13) ? budget : 1u << 13; }

/// The star kernels' blocks a multiprocessor by input: uniform cells over floats 4,4,4 up to 2^22
/// sites (the points fit in L2, a thread's registers matter more) and 8,6,6 above; integer
/// coordinates 6 everywhere (the registers live across the exact decision spill at 64); quantile
/// cells 8 everywhere.
inline StarBlocks default_star_blocks(std::size_t sites, bool uniform_cells, bool integer_coordinates) {
  if (uniform_cells && !integer_coordinates)
    return sites <= (std::size_t{1} << 22) ? StarBlocks{4, 4, 4} : StarBlocks{8, 6, 6};
  return integer_coordinates ? StarBlocks{6, 6, 6} : StarBlocks{8, 8, 8};
}

}  // namespace expanse::detail::cuda
