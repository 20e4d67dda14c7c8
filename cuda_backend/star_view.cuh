#pragma once
// How the emit reads a finished star (star_common.cuh's row and info): StarView.
#include <cstdint>

#include "star_common.cuh"

namespace expanse::detail::cuda {

/// Four consecutive row entries, 16-byte aligned: one load on the device.
struct RowQuad {
  int x, y, z, w;
};
EXPANSE_DEVICE_FORCE RowQuad load_quad(const int* row) {
#if defined(__CUDACC__)
  const int4 q = *reinterpret_cast<const int4*>(row);
  return {q.x, q.y, q.z, q.w};
#else
  return {row[0], row[1], row[2], row[3]};
#endif
}

/// Site o's star as the emit reads it. A closed star of one to eight neighbours (nearly every
/// interior site's) lies in its row's first 32-byte sector, and is loaded whole into e[], in
/// 16-byte words where all four are the star's; any other star is read from its row, an entry
/// at a time, as star_at reads it. Read an entry at a time, each entry was a sector of its own
/// across a warp (ncu, 4096^2 uniform, H100: 5.3 of each sector's 32 bytes used,
/// 238 M sectors for the triangles' kernel). Only the star's own words are loaded: those past
/// its degree were never written (compute-sanitizer's initcheck), and padding them in the walks
/// cost the star kernels 0.25-0.5 ms.
struct StarView {
  const int* star;
  std::uint32_t inf;
  int o;
  bool head;  ///< the whole star is in e[] (closed, one to eight neighbours)
  int e[8];

  EXPANSE_DEVICE_FORCE StarView(const int* star_rows, std::uint32_t info, int site)
      : star(star_rows),
        inf(info),
        o(site),
        head(star_start(info) == 0 && star_degree(info) >= 1 && star_degree(info) <= 8) {
    if (head) {
      const int deg = star_degree(info);
      const int* row = star + static_cast<std::size_t>(o) * kStar;
      if (deg >= 4) {
        const RowQuad x = load_quad(row);
        e[0] = x.x, e[1] = x.y, e[2] = x.z, e[3] = x.w;
      } else {
#pragma unroll
        for (int k = 0; k < 4; ++k) e[k] = k < deg ? row[k] : -1;
      }
      if (deg == 8) {
        const RowQuad y = load_quad(row + 4);
        e[4] = y.x, e[5] = y.y, e[6] = y.z, e[7] = y.w;
      } else {
#pragma unroll
        for (int k = 4; k < 8; ++k) e[k] = k < deg ? row[k] : -1;
      }
    }
  }
  EXPANSE_DEVICE_FORCE int degree() const { return star_degree(inf); }
  EXPANSE_DEVICE_FORCE bool closed() const { return star_closed(inf); }
  EXPANSE_DEVICE_FORCE int triangles() const { return closed() ? degree() : degree() - 1; }
  /// Entry t, t in [-1, degree + 1], wrapping as star_at (selects, not an indexed array: an
  /// index unknown at compile time would put e[] in local memory).
  EXPANSE_DEVICE_FORCE int at(int t) const {
    if (!head) return star_at(star, inf, o, t);
    const int deg = degree();
    t = t < 0 ? t + deg : t;
    t = t >= deg ? t - deg : t;
    t = t >= deg ? t - deg : t;
    int v = e[0];
#pragma unroll
    for (int k = 1; k < 8; ++k) v = t == k ? e[k] : v;
    return v;
  }
  /// Where u is in the star, or -1, as star_find.
  EXPANSE_DEVICE_FORCE int find(int u) const {
    if (!head) return star_find(star, inf, o, u);
    const int deg = degree();
    int p = -1;
#pragma unroll
    for (int k = 7; k >= 0; --k) p = k < deg && e[k] == u ? k : p;
    return p;
  }
  /// The star's triangles that o owns (it is their smallest vertex), bit t for the triangle
  /// (o, star t, star t + 1).
  EXPANSE_DEVICE_FORCE std::uint32_t owned_mask() const {
    const int tris = triangles();
    std::uint32_t mask = 0;
    if (head) {
#pragma unroll
      for (int t = 0; t < 8; ++t) {
        const int a = e[t], b = t + 1 < degree() ? e[(t + 1) & 7] : e[0];
        mask |= static_cast<std::uint32_t>(t < tris && o < a && o < b) << t;
      }
    } else {
      int a = at(0);
      for (int t = 0; t < tris; ++t) {
        const int b = at(t + 1);
        mask |= static_cast<std::uint32_t>(o < a && o < b) << t;
        a = b;
      }
    }
    return mask;
  }
};

}  // namespace expanse::detail::cuda
