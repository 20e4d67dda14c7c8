#version 450
// Adjacency of the per-site layout's output, from the stars star.comp stored (a second pass
// over the sites; the CUDA backend's emit kernel does the same). A triangle is emitted by its
// smallest site id, which numbers its triangles in star order from its output offset, so the
// index of any triangle follows from its owner's star.
//
// For a triangle (s, a, b) owned by s: the triangles across s-b and s-a are the next and previous
// ones in s's own star; the one across a-b is (b, a, r) with r read from a's star (or b's). When
// both a and b deferred, neither star exists: the slot is listed in `unresolved`, and the host
// pairs those slots up (they are as rare as pairs of adjacent deferred sites). A triangle whose
// owner deferred was not emitted: its slot is no_neighbor (-1), as for hull edges.
#extension GL_GOOGLE_include_directive : require

layout(local_size_x_id = 0) in;
layout(constant_id = 1) const int STAR_CAPACITY = 16;

layout(std430, set = 0, binding = 0) readonly buffer Star { int star[]; };
layout(std430, set = 0, binding = 1) readonly buffer SiteInfo { int site_info[]; };
layout(std430, set = 0, binding = 2) writeonly buffer Neighbors { int neighbors[]; };
layout(std430, set = 0, binding = 3) writeonly buffer Unresolved { int unresolved[]; };
// [4] unresolved slots, [5] loop cap hit (results void), [6] unresolved overflow
layout(std430, set = 0, binding = 4) buffer Counters { uint counters[]; };

layout(push_constant) uniform Params {
  int site_count;
  int first_site;
  int unresolved_capacity;
  int pad;
} params;

#include "star_common.glsl"

uint info_of(int s) { return uint(site_info[2 * s]); }

// Position of u in the star of o, or -1.
int star_find(int o, uint info, int u) {
  int deg = star_degree(info);
  for (int t = 0; t < deg; ++t)
    if (star_at_row(o * STAR_CAPACITY, info, t) == u) return t;
  return -1;
}

// Output index of the counter-clockwise triangle (x, y, z), or -1 if its owner deferred.
int triangle_index(int x, int y, int z) {
  int o = x, u = y, w = z;
  if (y < o && y < z) {
    o = y;
    u = z;
    w = x;
  } else if (z < o && z < y) {
    o = z;
    u = x;
    w = y;
  }
  uint info = info_of(o);
  if (star_deferred(info)) return -1;
  int base = site_info[2 * o + 1];
  if (base < 0) return -1;
  int deg = star_degree(info);
  int tris = star_closed(info) ? deg : deg - 1;
  int row = o * STAR_CAPACITY;
  int count = 0;
  for (int t = 0; t < tris; ++t) {
    int a = star_at_row(row, info, t), b = star_at_row(row, info, t + 1);
    if (a == u) return b == w ? base + count : -1;
    if (o < a && o < b) ++count;
  }
  return -1;
}

void main() {
  int s = params.first_site + int(gl_GlobalInvocationID.x);
  if (s >= params.site_count) return;
  uint info = info_of(s);
  if (star_deferred(info)) return;
  int at_out = site_info[2 * s + 1];
  if (at_out < 0) return;  // owns no triangle
  int deg = star_degree(info);
  bool closed = star_closed(info);
  int tris = closed ? deg : deg - 1;
  int row = s * STAR_CAPACITY;
  for (int t = 0; t < tris; ++t) {
    int a = star_at_row(row, info, t), b = star_at_row(row, info, t + 1);
    if (!(s < a && s < b)) continue;
    // Opposite s: (b, a, r).
    int across_ab = -1;
    int r = -1;
    uint ia = info_of(a), ib = info_of(b);
    if (!star_deferred(ia)) {
      int p = star_find(a, ia, b);
      if (p >= 0 && (p > 0 || star_closed(ia))) r = star_at_row(a * STAR_CAPACITY, ia, p - 1);
    } else if (!star_deferred(ib)) {
      int q = star_find(b, ib, a);
      if (q >= 0 && (q < star_degree(ib) - 1 || star_closed(ib)))
        r = star_at_row(b * STAR_CAPACITY, ib, q + 1);
    } else {
      uint at = atomicAdd(counters[4], 1u);
      if (int(at) < params.unresolved_capacity) unresolved[int(at)] = 3 * at_out;
      else atomicAdd(counters[6], 1u);
    }
    if (r >= 0) across_ab = triangle_index(b, a, r);
    // Opposite a: (s, b, next).
    int across_bs = -1;
    if (closed || t + 2 < deg) across_bs = triangle_index(s, b, star_at_row(row, info, t + 2));
    // Opposite b: (s, previous, a).
    int across_sa = -1;
    if (closed || t >= 1) across_sa = triangle_index(s, star_at_row(row, info, t - 1), a);
    neighbors[3 * at_out] = across_ab;
    neighbors[3 * at_out + 1] = across_bs;
    neighbors[3 * at_out + 2] = across_sa;
    ++at_out;
  }
  // Canary for lavapipe's loop cap (see star.comp): if it was reached, loops above may have
  // been cut short, and the host discards the whole adjacency.
  int canary = 0;
  for (int i = 0; i < min(params.site_count, 2); ++i) ++canary;
  if (canary != 2) atomicAdd(counters[5], 1u);
}
