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

#include "backends/vulkan/tuning.hpp"
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

/// Every stride-th site (Morton order: spread over the plane), as star_cell_sample picks them,
/// which is all the grid's planning reads: where the device prepared the sites, it sends these
/// back first and the rest while the stars grow.
struct SiteSample {
  const Point2* points = nullptr;  ///< sample k at points[k * step]
  std::size_t step = 1, count = 0;
  const Point2& operator[](std::size_t k) const { return points[k * step]; }
};

/// The sample's stride for n sites: about 2^20 of them.
inline std::size_t star_cell_sample_stride(std::size_t n) { return std::max<std::size_t>(1, n >> 20); }

/// The sample of these sites, in place.
inline SiteSample star_cell_sample(const SiteSet& sites) {
  const std::size_t n = std::size_t(sites.size()), stride = star_cell_sample_stride(n);
  return {sites.points.data(), stride, n / stride};
}

/// The star grid for n sites in `bounds`, planned from their sample: quantile cells where uniform ones would crowd the typical
/// site's cells (`cells` other than automatic forces one kind), about `per_bucket` sites to a
/// cell; at most as many cells as a buffer of `max_buffer` bytes holds starts for.
StarCells plan_star_cells(const SiteSample& sample, std::size_t n, const Box& bounds, double per_bucket,
                          VkDeviceSize max_buffer, Tuning::Cells cells);

}  // namespace expanse::detail::vk
