#include "io/picture_layout.hpp"

#include <algorithm>
#include <limits>
#include <string>

#include "expanse/error.hpp"

namespace expanse::io_detail {

PictureLayout lay_out_picture(std::span<const Point2> points, const Mesh& mesh,
                              const PictureOptions& options) {
  if (options.size < 16 || options.size > 16384) {
    throw Error(ErrorCode::invalid_argument, "picture size must be within 16..16384 pixels");
  }
  if (options.margin < 0 || 2 * options.margin >= options.size) {
    throw Error(ErrorCode::invalid_argument, "picture margin must be within 0..size/2");
  }
  if (!options.triangle_origin.empty() && options.triangle_origin.size() != mesh.triangles.size()) {
    throw Error(ErrorCode::invalid_argument,
                "triangle_origin has " + std::to_string(options.triangle_origin.size()) +
                    " entries for " + std::to_string(mesh.triangles.size()) + " triangles");
  }
  const auto n = static_cast<std::int64_t>(points.size());
  auto check_index = [&](std::int32_t v) {
    if (v < 0 || v >= n) {
      throw Error(ErrorCode::invalid_argument,
                  "mesh refers to point " + std::to_string(v) + " of " + std::to_string(n));
    }
  };
  for (const Triangle& t : mesh.triangles) std::for_each(t.begin(), t.end(), check_index);
  std::for_each(mesh.hull.begin(), mesh.hull.end(), check_index);

  // Halved coordinates cannot overflow when subtracted, even for inputs near 1e308.
  double min_x = std::numeric_limits<double>::infinity(), min_y = min_x;
  double max_x = -min_x, max_y = -min_x;
  for (const Point2& p : points) {
    min_x = std::min(min_x, p.x * 0.5);
    max_x = std::max(max_x, p.x * 0.5);
    min_y = std::min(min_y, p.y * 0.5);
    max_y = std::max(max_y, p.y * 0.5);
  }
  PictureLayout layout;
  const double extent_x = points.empty() ? 0.0 : max_x - min_x;
  const double extent_y = points.empty() ? 0.0 : max_y - min_y;
  const double extent = std::max(extent_x, extent_y);
  const double inner = options.size - 2.0 * options.margin;
  const double scale = extent > 0 ? inner / extent : 1.0;
  layout.width = 2 * options.margin + std::max(1, static_cast<int>(extent_x * scale + 0.5));
  layout.height = 2 * options.margin + std::max(1, static_cast<int>(extent_y * scale + 0.5));
  layout.at.reserve(points.size());
  for (const Point2& p : points) {
    // y grows upwards in the plane and downwards in images.
    layout.at.push_back({options.margin + (p.x * 0.5 - min_x) * scale,
                         layout.height - options.margin - (p.y * 0.5 - min_y) * scale});
  }

  layout.edges.reserve(mesh.triangles.size() * 3);
  for (const Triangle& t : mesh.triangles) {
    for (int k = 0; k < 3; ++k) {
      const std::int32_t a = t[k], b = t[(k + 1) % 3];
      layout.edges.emplace_back(std::min(a, b), std::max(a, b));
    }
  }
  std::sort(layout.edges.begin(), layout.edges.end());
  layout.edges.erase(std::unique(layout.edges.begin(), layout.edges.end()), layout.edges.end());

  for (std::size_t t = 0; t < options.triangle_origin.size(); ++t) {
    if (options.triangle_origin[t] != 0) layout.seam_triangles.push_back(static_cast<std::int32_t>(t));
  }
  layout.draw_points = options.draw_points > 0 || (options.draw_points < 0 && points.size() <= 20000);
  return layout;
}

}  // namespace expanse::io_detail
