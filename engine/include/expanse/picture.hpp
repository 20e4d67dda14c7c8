#pragma once
// Pictures of a triangulation a person can look at: SVG (vector) and PNG (Expanse's own small
// rasteriser, encoded with libpng). Both writers are atomic like the file writers in io.hpp.
#include <cstdint>
#include <filesystem>
#include <span>
#include <vector>

#include "expanse/mesh.hpp"
#include "expanse/types.hpp"

namespace expanse {

struct PictureOptions {
  /// Length in pixels of the picture's longer side; the other side follows the points' aspect.
  int size = 1024;
  /// Empty border around the drawing, in pixels.
  int margin = 16;
  /// Draw the sites as dots: 1 always, 0 never, -1 only when there are few (<= 20000).
  int draw_points = -1;
  /// Optional, one entry per triangle: 0 = made by the device's front growth, 1 = made by the
  /// CPU seam stage (drawn filled in a different colour, as in the paper's Fig. IV.4/IV.5).
  std::vector<std::uint8_t> triangle_origin;
};

/// Writes an SVG of mesh over points: triangle edges, the convex hull, optionally the sites.
/// Preconditions: mesh indexes points; points finite; triangle_origin empty or one per
/// triangle (else Error(invalid_argument)). Throws Error(io_error) on failure (no file left).
void write_svg(const std::filesystem::path& path, std::span<const Point2> points,
               const Mesh& mesh, const PictureOptions& options = {});

/// Writes the same picture as an 8-bit RGB PNG. Preconditions as write_svg, and
/// 16 <= options.size <= 16384.
void write_png(const std::filesystem::path& path, std::span<const Point2> points,
               const Mesh& mesh, const PictureOptions& options = {});

}  // namespace expanse
