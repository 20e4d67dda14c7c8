// SVG pictures: one path for all edges keeps files small and fast to render.
#include <charconv>
#include <string>

#include "expanse/picture.hpp"
#include "io/atomic_file.hpp"
#include "io/picture_layout.hpp"

namespace expanse {
namespace {

using io_detail::Rgb;

// Two decimals are a hundredth of a pixel: plenty, and much shorter than round-trip doubles.
void coord(io_detail::TextWriter& out, double v) {
  char tmp[48];
  auto [end, ec] = std::to_chars(tmp, tmp + sizeof tmp, v, std::chars_format::fixed, 2);
  out.text(std::string_view(tmp, static_cast<std::size_t>(end - tmp)));
}

void point(io_detail::TextWriter& out, const io_detail::Pixel& p) {
  coord(out, p.x);
  out.ch(',');
  coord(out, p.y);
}

std::string colour(Rgb c) {
  char tmp[8];
  static const char* hex = "0123456789abcdef";
  tmp[0] = '#';
  const std::uint8_t v[3] = {c.r, c.g, c.b};
  for (int i = 0; i < 3; ++i) {
    tmp[1 + 2 * i] = hex[v[i] >> 4];
    tmp[2 + 2 * i] = hex[v[i] & 15];
  }
  return std::string(tmp, 7);
}

}  // namespace

void write_svg(const std::filesystem::path& path, std::span<const Point2> points, const Mesh& mesh,
               const PictureOptions& options) {
  const io_detail::PictureLayout layout = io_detail::lay_out_picture(points, mesh, options);
  io_detail::AtomicFile file(path);
  io_detail::TextWriter out(file);
  const std::string w = std::to_string(layout.width), h = std::to_string(layout.height);
  out.text("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n")
      .text("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + w + "\" height=\"" + h +
            "\" viewBox=\"0 0 " + w + " " + h + "\">\n")
      .text("<rect width=\"100%\" height=\"100%\" fill=\"" + colour(io_detail::kBackground) + "\"/>\n");

  if (!layout.seam_triangles.empty()) {
    out.text("<path fill=\"" + colour(io_detail::kSeamFill) + "\" stroke=\"none\" d=\"");
    for (std::int32_t t : layout.seam_triangles) {
      const Triangle& tri = mesh.triangles[static_cast<std::size_t>(t)];
      out.ch('M');
      point(out, layout.at[tri[0]]);
      out.ch('L');
      point(out, layout.at[tri[1]]);
      out.ch('L');
      point(out, layout.at[tri[2]]);
      out.ch('Z');
    }
    out.text("\"/>\n");
  }

  if (!layout.edges.empty()) {
    out.text("<path fill=\"none\" stroke=\"" + colour(io_detail::kEdge) +
             "\" stroke-width=\"0.6\" stroke-linecap=\"round\" d=\"");
    for (const auto& [a, b] : layout.edges) {
      out.ch('M');
      point(out, layout.at[a]);
      out.ch('L');
      point(out, layout.at[b]);
    }
    out.text("\"/>\n");
  }

  if (!mesh.hull.empty()) {
    // Without triangles the hull is the sites in order along a line: an open polyline.
    out.text(mesh.triangles.empty() ? "<polyline" : "<polygon");
    out.text(" fill=\"none\" stroke=\"" + colour(io_detail::kHull) +
             "\" stroke-width=\"2\" stroke-linejoin=\"round\" points=\"");
    for (std::int32_t v : mesh.hull) {
      point(out, layout.at[v]);
      out.space();
    }
    out.text("\"/>\n");
  }

  if (layout.draw_points) {
    out.text("<g fill=\"" + colour(io_detail::kPoint) + "\">\n");
    for (const io_detail::Pixel& p : layout.at) {
      out.text("<circle cx=\"");
      coord(out, p.x);
      out.text("\" cy=\"");
      coord(out, p.y);
      out.text("\" r=\"1.5\"/>\n");
    }
    out.text("</g>\n");
  }
  out.text("</svg>\n");
  out.flush();
  file.commit();
}

}  // namespace expanse
