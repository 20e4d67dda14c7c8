// PNG pictures: a small rasteriser (no anti-aliasing) and libpng's simplified API, which
// reports errors by return value instead of longjmp, so no C++ object is ever skipped over.
#include <png.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "expanse/error.hpp"
#include "expanse/picture.hpp"
#include "io/atomic_file.hpp"
#include "io/picture_layout.hpp"

namespace expanse {
namespace {

using io_detail::Pixel;
using io_detail::Rgb;

class Canvas {
 public:
  Canvas(int width, int height) : width_(width), height_(height), rgb_(std::size_t(width) * height * 3) {
    for (std::size_t i = 0; i < rgb_.size(); i += 3) set_at(i, io_detail::kBackground);
  }

  void plot(int x, int y, Rgb c) {
    if (x < 0 || y < 0 || x >= width_ || y >= height_) return;
    set_at((std::size_t(y) * width_ + x) * 3, c);
  }

  void square(int x, int y, int radius, Rgb c) {
    for (int dy = -radius; dy <= radius; ++dy)
      for (int dx = -radius; dx <= radius; ++dx) plot(x + dx, y + dy, c);
  }

  // Bresenham between pixel centres; `radius` > 0 thickens the line with a square brush.
  void line(Pixel a, Pixel b, Rgb c, int radius = 0) {
    int x0 = static_cast<int>(std::floor(a.x)), y0 = static_cast<int>(std::floor(a.y));
    const int x1 = static_cast<int>(std::floor(b.x)), y1 = static_cast<int>(std::floor(b.y));
    const int dx = std::abs(x1 - x0), sx = x0 < x1 ? 1 : -1;
    const int dy = -std::abs(y1 - y0), sy = y0 < y1 ? 1 : -1;
    int err = dx + dy;
    for (;;) {
      radius > 0 ? square(x0, y0, radius, c) : plot(x0, y0, c);
      if (x0 == x1 && y0 == y1) break;
      const int e2 = 2 * err;
      if (e2 >= dy) {
        err += dy;
        x0 += sx;
      }
      if (e2 <= dx) {
        err += dx;
        y0 += sy;
      }
    }
  }

  // Fills the pixels whose centres lie inside the triangle (either orientation).
  void fill(Pixel a, Pixel b, Pixel c, Rgb colour) {
    const int x_lo = std::max(0, static_cast<int>(std::floor(std::min({a.x, b.x, c.x}))));
    const int x_hi = std::min(width_ - 1, static_cast<int>(std::ceil(std::max({a.x, b.x, c.x}))));
    const int y_lo = std::max(0, static_cast<int>(std::floor(std::min({a.y, b.y, c.y}))));
    const int y_hi = std::min(height_ - 1, static_cast<int>(std::ceil(std::max({a.y, b.y, c.y}))));
    auto side = [](Pixel p, Pixel q, double x, double y) {
      return (q.x - p.x) * (y - p.y) - (q.y - p.y) * (x - p.x);
    };
    for (int y = y_lo; y <= y_hi; ++y) {
      for (int x = x_lo; x <= x_hi; ++x) {
        const double px = x + 0.5, py = y + 0.5;
        const double s0 = side(a, b, px, py), s1 = side(b, c, px, py), s2 = side(c, a, px, py);
        if ((s0 >= 0 && s1 >= 0 && s2 >= 0) || (s0 <= 0 && s1 <= 0 && s2 <= 0)) plot(x, y, colour);
      }
    }
  }

  const std::vector<std::uint8_t>& rgb() const { return rgb_; }

 private:
  void set_at(std::size_t i, Rgb c) {
    rgb_[i] = c.r;
    rgb_[i + 1] = c.g;
    rgb_[i + 2] = c.b;
  }
  int width_, height_;
  std::vector<std::uint8_t> rgb_;
};

std::vector<std::uint8_t> encode_png(const Canvas& canvas, int width, int height,
                                     const std::filesystem::path& path) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  image.width = static_cast<png_uint_32>(width);
  image.height = static_cast<png_uint_32>(height);
  image.format = PNG_FORMAT_RGB;
  png_alloc_size_t bytes = 0;
  // The first call measures, the second encodes.
  if (!png_image_write_to_memory(&image, nullptr, &bytes, 0, canvas.rgb().data(), 0, nullptr)) {
    throw Error(ErrorCode::io_error, path.string() + ": PNG encoding failed: " + image.message);
  }
  std::vector<std::uint8_t> png(bytes);
  if (!png_image_write_to_memory(&image, png.data(), &bytes, 0, canvas.rgb().data(), 0, nullptr)) {
    throw Error(ErrorCode::io_error, path.string() + ": PNG encoding failed: " + image.message);
  }
  png.resize(bytes);
  return png;
}

}  // namespace

void write_png(const std::filesystem::path& path, std::span<const Point2> points, const Mesh& mesh,
               const PictureOptions& options) {
  const io_detail::PictureLayout layout = io_detail::lay_out_picture(points, mesh, options);
  Canvas canvas(layout.width, layout.height);
  for (std::int32_t t : layout.seam_triangles) {
    const Triangle& tri = mesh.triangles[static_cast<std::size_t>(t)];
    canvas.fill(layout.at[tri[0]], layout.at[tri[1]], layout.at[tri[2]], io_detail::kSeamFill);
  }
  for (const auto& [a, b] : layout.edges) canvas.line(layout.at[a], layout.at[b], io_detail::kEdge);
  for (std::size_t i = 0; i + 1 < mesh.hull.size(); ++i) {
    canvas.line(layout.at[mesh.hull[i]], layout.at[mesh.hull[i + 1]], io_detail::kHull, 1);
  }
  if (!mesh.triangles.empty() && mesh.hull.size() > 2) {
    canvas.line(layout.at[mesh.hull.back()], layout.at[mesh.hull.front()], io_detail::kHull, 1);
  }
  if (layout.draw_points) {
    for (const Pixel& p : layout.at) {
      canvas.square(static_cast<int>(std::floor(p.x)), static_cast<int>(std::floor(p.y)), 1, io_detail::kPoint);
    }
  }
  const std::vector<std::uint8_t> png = encode_png(canvas, layout.width, layout.height, path);
  io_detail::write_file_atomically(
      path, std::string_view(reinterpret_cast<const char*>(png.data()), png.size()));
}

}  // namespace expanse
