#pragma once
// The host's side of sorting sites into cells: the star grid's counting sort (CPU devices, and
// cells too crowded for bucket.comp's ranking) and the mapping of the device's triangles back to
// SiteSet ids; the paper layout's grid frame.
#include <cstdint>
#include <vector>

#include "backends/backend.hpp"
#include "backends/vulkan/star_cells.hpp"
#include "backends/vulkan/vk_context.hpp"

namespace expanse::detail::vk {

/// A cells x cells grid over the sites' bounding box (cell_coord's origin and scale).
struct GridFrame {
  int cells = 0;
  double origin[2]{}, inv_width[2]{};

  GridFrame() = default;
  GridFrame(const SiteSet& sites, int cells_per_side) : cells(cells_per_side) {
    origin[0] = sites.bounds.min_x;
    origin[1] = sites.bounds.min_y;
    const double wx = sites.bounds.max_x - sites.bounds.min_x;
    const double wy = sites.bounds.max_y - sites.bounds.min_y;
    inv_width[0] = wx > 0 ? double(cells) / wx : 0.0;
    inv_width[1] = wy > 0 ? double(cells) / wy : 0.0;
  }
};

/// Sorted id -> SiteSet id, when the host bucketed the star grid.
struct StarGrid {
  std::vector<std::int32_t> to_site;
};

/// The host's counting sort (bucket_stars) into the star kernel's sites, cell starts and hull
/// predecessors: in place when the buffers are host-visible, else through the staging ring (the
/// star kernel's recording starts with a barrier, which orders it after those copies). Used on
/// CPU devices, and where a cell is too crowded for the device's ranking (bucket.comp, MAX_CELL).
void bucket_on_host(Context& ctx, const GrowInput& input, const StarCells& plan, Buffer& sites,
                    Buffer& cell_start, Buffer& predecessor, StarGrid& grid);

/// Device triangles (sorted ids) -> partial.triangles (SiteSet ids, room already made), checking
/// every id: the host's twin of bucket.comp's restore pass, when the host bucketed.
void restore_on_host(const StarGrid& g, const std::int32_t* raw, std::size_t count,
                     PartialTriangulation& partial);

}  // namespace expanse::detail::vk
