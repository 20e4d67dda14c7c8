#pragma once
// What the SVG and PNG writers share: where each site lands in the picture, which edges to draw
// (each once), which triangles to fill, and the palette.
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "expanse/mesh.hpp"
#include "expanse/picture.hpp"
#include "expanse/types.hpp"

namespace expanse::io_detail {

struct Pixel {
  double x = 0, y = 0;
};

struct PictureLayout {
  int width = 0, height = 0;
  std::vector<Pixel> at;                            ///< pixel position of every input point
  std::vector<std::pair<std::int32_t, std::int32_t>> edges;  ///< triangle edges, each once
  std::vector<std::int32_t> seam_triangles;         ///< triangles to fill (origin 1)
  bool draw_points = false;
};

/// Validates options against the mesh and computes the layout. Throws Error(invalid_argument).
PictureLayout lay_out_picture(std::span<const Point2> points, const Mesh& mesh,
                              const PictureOptions& options);

struct Rgb {
  std::uint8_t r, g, b;
};
inline constexpr Rgb kBackground{255, 255, 255};
inline constexpr Rgb kEdge{43, 76, 126};
inline constexpr Rgb kSeamFill{251, 201, 140};
inline constexpr Rgb kHull{192, 57, 43};
inline constexpr Rgb kPoint{0, 0, 0};

}  // namespace expanse::io_detail
