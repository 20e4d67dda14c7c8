#pragma once
// The per-site layout's bucket grid, as host code shared by star_kernels.cu (which builds it on
// the device) and star_host.hpp (which builds the same grid on the CPU for tests and work
// counts): its shape, the sample behind the quantile boundaries, and the boundaries themselves.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "device_geometry.cuh"
#include "grid/quantile_tails.hpp"
#include "input/site_set.hpp"
#include "predicates/exact_lattice.hpp"
#include "tuning.hpp"

namespace expanse::detail::cuda {

struct GridShape {
  double min_x, min_y, inv_w, inv_h, cell_w, cell_h;
  int gx, gy;
};

/// Square-ish cells over the sites' box, about sites_per_bucket sites per cell on average.
inline GridShape make_grid_shape(const Box& box, std::size_t n, double sites_per_bucket) {
  GridShape s{};
  const double w = box.max_x - box.min_x, h = box.max_y - box.min_y;
  const double cells = std::max(1.0, static_cast<double>(n) / std::max(0.25, sites_per_bucket));
  double side = std::sqrt(std::max(w, 1e-300) * std::max(h, 1e-300) / cells);
  if (!(side > 0.0)) side = std::max(w, h);
  auto count = [&](double extent) {
    const double c = std::ceil(extent / side);
    return static_cast<int>(std::clamp(c, 1.0, 16384.0));
  };
  s.gx = count(w);
  s.gy = count(h);
  s.min_x = box.min_x;
  s.min_y = box.min_y;
  s.inv_w = w > 0 ? s.gx / w : 0.0;
  s.inv_h = h > 0 ? s.gy / h : 0.0;
  s.cell_w = w > 0 ? w / s.gx : 1.0;
  s.cell_h = h > 0 ? h / s.gy : 1.0;
  return s;
}

/// Uniform cells hold this many times the layout's sites_per_bucket when the coordinates are not
/// integers; quantile cells, and uniform cells of integer inputs, hold sites_per_bucket. A scan
/// costs its rows as much as its candidates, and since the first pass walks light (no row cuts,
/// no exact path) coarser uniform cells pay. H100, GPU-only, uniform input, commit b49d802, two
/// rounds alternated at sites per cell 3.5 / 3.06 / 2.84 / 2.625: 4096^2 31.54-31.65 /
/// 31.33-31.40 / 31.28-31.30 / 31.21-31.23 ms; 2048^2 9.55 / 9.51 / - / 9.48; 1024^2 3.35 /
/// 3.27 / - / 3.31; 512^2 1.75 / 1.65 / - / 1.72. Finer still (2.4 and 2.25 a cell): 31.23 and
/// 31.29 ms against 31.24-31.28. The integer lattice lost at 2.5 to 3.5 (4096^2 25.3-25.8
/// against 24.0-25.0 ms) and keeps sites_per_bucket, its cells 2 x 2 of its points.
inline constexpr double kUniformCellsScale = 1.3125;

/// The shape of uniform cells for these sites (kUniformCellsScale).
inline GridShape uniform_cells_shape(const Box& box, std::size_t n, double sites_per_bucket, bool integer_coordinates) {
  return make_grid_shape(box, n, integer_coordinates ? sites_per_bucket : kUniformCellsScale * sites_per_bucket);
}

/// The shape of quantile cells: as many columns as rows, no more cells than `uniform` has. Quantile
/// boundaries give every column and every row its share of the sites whatever the box, so the
/// box's aspect, which sizes uniform cells, says nothing about them; a heavy tail stretches the
/// box (kuzmin 4096^2, seed 1: 13 times taller than wide), and columns 13 times as many as rows
/// (in sites) made the star kernel's cells as elongated.
inline GridShape quantile_shape(const GridShape& uniform, const Box& box) {
  GridShape q = uniform;
  const double w = box.max_x - box.min_x, h = box.max_y - box.min_y;
  const int side = std::max(1, static_cast<int>(std::floor(std::sqrt(static_cast<double>(uniform.gx) * uniform.gy))));
  q.gx = q.gy = side;
  q.inv_w = w > 0 ? side / w : 0.0;
  q.inv_h = h > 0 ? side / h : 0.0;
  q.cell_w = w > 0 ? w / side : 1.0;
  q.cell_h = h > 0 ? h / side : 1.0;
  return q;
}

/// Sets g's shape: its origin, scales and cells per axis.
inline void apply_shape(GridView& g, const GridShape& shape) {
  g.min_x = shape.min_x;
  g.min_y = shape.min_y;
  g.inv_w = shape.inv_w;
  g.inv_h = shape.inv_h;
  g.cell_w = shape.cell_w;
  g.cell_h = shape.cell_h;
  g.gx = shape.gx;
  g.gy = shape.gy;
}

/// GridView of a shape over the sites' box (pointers left for the caller to set).
inline GridView make_grid_view(const GridShape& shape, const Box& box) {
  GridView g{};
  apply_shape(g, shape);
  g.max_x = box.max_x;
  g.max_y = box.max_y;
  return g;
}


/// The first box of every apex search (GridView::first_reach, first_offset): star.comp's box
/// (reach and offset 1) but on uniform cells up to 2^20 sites that are not integers, where a box
/// 3/4 as wide, half as far left of the edge, pays. Its fewer candidates (uniform 4096^2: 79.9
/// -> 74.5 predicates a site) cost more second boxes, and where the GPU is full that loses; where
/// a few waves of blocks and their slowest walks set the time, it wins. GPU-only, two rounds
/// alternated: uniform 512^2 2.86 -> 2.65 ms (H100), 2.76 -> 2.61 (H200), 1024^2 5.21 / 5.23 ->
/// 4.97 / 4.96 (H200), but 4096^2 40.3 -> 43.9 (H100); on quantile cells gaussian 1024^2 6.45 ->
/// 7.35 (H200), kuzmin and gaussian 4096^2 slower too; the integer lattice 512^2 0.93 -> 1.12 ms,
/// 1024^2 2.20 -> 2.40 (H100). Larger boxes (reach up to 2, offset up to 1.5) lost everywhere.
struct FirstBoxShape {
  double reach = 1.0, offset = 1.0;
};
inline FirstBoxShape first_box_shape(bool uniform_cells, std::size_t sites, bool integer_coordinates) {
  if (uniform_cells && !integer_coordinates && sites <= (std::size_t{1} << 20)) return {0.75, 0.5};
  return {};
}
inline void apply_first_box(GridView& g, bool uniform_cells, const SiteSet& sites) {
  const FirstBoxShape shape = first_box_shape(uniform_cells, sites.points.size(), sites.integer_coordinates);
  g.first_reach = shape.reach;
  g.first_offset = shape.offset;
}

/// How many coordinates the quantile boundaries are taken from.
inline int quantile_sample_count(std::size_t n) {
  return static_cast<int>(std::min<std::size_t>(n, std::size_t{1} << 18));
}

/// splitmix64's finaliser: every bit of z stirred into every bit of the result.
EXPANSE_HOST_DEVICE std::uint64_t mix_bits(std::uint64_t z) {
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

/// The site behind sample i: a hashed index, so that ordered inputs (row-major grids) do not alias.
EXPANSE_HOST_DEVICE int quantile_sample_site(int i, int n, int samples) {
  if (samples >= n) return i;
  return static_cast<int>(mix_bits(static_cast<std::uint64_t>(i) + 0x9E3779B97F4A7C15ull) % static_cast<std::uint64_t>(n));
}

/// Uniform cells or quantile cells. Quantile cells keep a cell's share of the sites even where
/// they cluster, but every cell lookup is a search of the boundaries; uniform cells are looked
/// up by a multiplication (H100, star kernel at 4096^2: uniform input 66.7 ms against 78.9 with
/// the guided search, lattice 181 against 245). So the sample decides: a kEvennessBins^2
/// histogram over the sites' box, and uniform cells where no bin holds more than twice the mean (a uniform sample of 2^15 or more sites
/// stays far below: 32 per bin at least, the largest of 1024 Poisson bins about 1.5x the mean);
/// clusters and long tails (gaussian, kuzmin) exceed it many times over.
inline constexpr int kEvennessBins = 32;
inline constexpr int kEvennessMinSamples = 1 << 15;

/// The histogram's frame over the sites' box (not flat): origin and bins per unit.
struct EvennessFrame {
  double min_x, min_y, scale_x, scale_y;
};
inline EvennessFrame evenness_frame(const GridView& g) {
  return {g.min_x, g.min_y, kEvennessBins / (g.max_x - g.min_x), kEvennessBins / (g.max_y - g.min_y)};
}

/// The histogram bin of (x, y), in [0, kEvennessBins^2).
EXPANSE_HOST_DEVICE int evenness_bin(const EvennessFrame& f, double x, double y) {
  auto bin = [](double v, double lo, double scale) {
    const double t = (v - lo) * scale;
    return t <= 0.0 ? 0 : t >= kEvennessBins - 1 ? kEvennessBins - 1 : static_cast<int>(t);
  };
  return bin(y, f.min_y, f.scale_y) * kEvennessBins + bin(x, f.min_x, f.scale_x);
}

/// Whether `samples` sites whose fullest histogram bin holds `max_count` are spread evenly
/// enough for uniform cells (see kEvennessBins). Too small a sample says no.
inline bool evenly_spread(unsigned max_count, int samples) {
  if (samples < kEvennessMinSamples) return false;
  return static_cast<double>(max_count) <= 2.0 * samples / (kEvennessBins * kEvennessBins);
}

/// Whether quantile cells copy their outer columns (TailColumns in device_geometry.cuh): where
/// the x-axis' tails are heavy (quantile_tails weighs them), unless `forced`. A gaussian's are
/// not, and on the H100 its scans across cost it 1.3 ms at 4096^2, though counted on the CPU
/// they saved it 2% of its lock-step work.
inline bool tail_columns_wanted(bool heavy_x_tails, Forced forced) {
  return forced == Forced::automatic ? heavy_x_tails : forced == Forced::on;
}

/// Whether an axis of `cells` columns gets a guide: with fewer than 8 the full search is as short.
inline bool quantile_guided(int cells) { return cells >= 8; }

}  // namespace expanse::detail::cuda
