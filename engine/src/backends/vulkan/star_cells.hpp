#pragma once
// The per-site layout's star grid: how many cells, and which kind. Uniform cells are looked up
// by a multiplication (cells.glsl); quantile cells (quantile_cells.glsl) by a search of
// per-axis boundaries taken at the quantiles of a sample of the sites, so that clustered and
// heavy-tailed inputs keep every row and column of cells at its share of the sites. The host's
// twins of the shaders' lookups are here, for its counting sort.
#include <vulkan/vulkan.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "input/site_set.hpp"

namespace expanse::detail::vk {

/// Cell index along one axis of uniform cells: the same two correctly rounded operations as
/// cell_coord() in shaders/include/cells.glsl (the engine builds with -ffp-contract=off), so
/// host bucketing and device box tests agree bit for bit.
inline int cell_coord(double x, double origin, double inv_width, int cells) {
  const double t = (x - origin) * inv_width;
  return int(std::clamp(std::floor(t), 0.0, double(cells - 1)));
}

struct StarCells {
  int cells = 0;  ///< per side
  /// Uniform cells: cell_coord's origin and scale (also set, unused by the lookups, with
  /// quantile cells).
  double origin[2]{}, inv_width[2]{};
  bool quantile = false;
  /// Quantile cells: cells - 1 ascending boundaries for x, then cells - 1 for y.
  std::vector<double> bounds;

  /// The cell of a coordinate, as the shaders find it.
  int x(double v) const { return quantile ? quantile_cell(v, 0) : cell_coord(v, origin[0], inv_width[0], cells); }
  int y(double v) const {
    return quantile ? quantile_cell(v, std::size_t(cells - 1)) : cell_coord(v, origin[1], inv_width[1], cells);
  }

 private:
  // quantile_cells.glsl's quantile_cell: the count of boundaries at or below v.
  int quantile_cell(double v, std::size_t base) const {
    const auto first = bounds.begin() + std::ptrdiff_t(base);
    return int(std::upper_bound(first, first + (cells - 1), v) - first);
  }
};

/// The star grid for these sites: quantile cells where uniform ones would crowd the typical
/// site's cells (EXPANSE_VULKAN_CELLS=uniform or =quantile overrides), about `per_bucket` sites
/// to a cell;
/// at most as many cells as a buffer of `max_buffer` bytes holds starts for.
StarCells plan_star_cells(const SiteSet& sites, double per_bucket, VkDeviceSize max_buffer);

}  // namespace expanse::detail::vk
