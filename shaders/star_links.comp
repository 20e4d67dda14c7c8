#version 450
// Adjacency of the per-site layout's output, from the stars star.comp stored (a second pass
// over the sites; the CUDA backend's emit kernel does the same). A triangle is emitted by its
// smallest site id, which numbers its triangles in star order from its output offset, so the
// index of any triangle follows from its owner's star and owned-triangle mask.
//
// For a triangle (s, a, b) owned by s: the triangles across s-b and s-a are the next and previous
// ones in s's own star; the one across a-b is (b, a, r) with r read from a's star (or b's). When
// both a and b deferred, neither star exists: the slot is listed in `unresolved`, and the host
// pairs those slots up (they are as rare as pairs of adjacent deferred sites). A triangle whose
// owner deferred was not emitted: its slot is no_neighbor (-1), as for hull edges.
#extension GL_GOOGLE_include_directive : require

#include "host_device.h"

layout(local_size_x_id = 0) in;
layout(constant_id = LINKS_SPEC_CAPACITY) const int STAR_CAPACITY = 16;

layout(std430, set = 0, binding = 0) readonly buffer Star { ivec4 star4[]; };
layout(std430, set = 0, binding = 1) readonly buffer SiteInfo { ivec2 site_info[]; };
layout(std430, set = 0, binding = 2) writeonly buffer Neighbors { int neighbors[]; };
layout(std430, set = 0, binding = 3) writeonly buffer Unresolved { int unresolved[]; };
// [4] unresolved slots, [5] loop cap hit (results void), [6] unresolved overflow
layout(std430, set = 0, binding = 4) buffer Counters { uint counters[]; };

layout(push_constant) uniform Push { LinkParams params; };

#include "star_common.glsl"

StarRow load_row(int s) {
  return StarRow(star4[4 * s], star4[4 * s + 1], star4[4 * s + 2], star4[4 * s + 3]);
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
  ivec2 record = site_info[o];
  uint info = uint(record.x);
  if (star_deferred(info) || record.y < 0) return -1;
  StarRow r = load_row(o);
  int t = star_find(r, info, u);
  if (t < 0 || t >= star_triangles(info) || star_at(r, info, t + 1) != w) return -1;
  return star_output(record.y, info, t);
}

void main() {
  int s = params.first_site + int(gl_GlobalInvocationID.x);
  if (s >= params.site_count) return;
  ivec2 record = site_info[s];
  uint info = uint(record.x);
  int at_out = record.y;
  if (star_deferred(info) || at_out < 0) return;  // deferred, or owns no triangle
  int deg = star_degree(info);
  bool closed = star_closed(info);
  StarRow row = load_row(s);
  for (uint left = star_owned(info); left != 0u; left &= left - 1u) {
    int t = findLSB(left);
    int a = star_at(row, info, t), b = star_at(row, info, t + 1);
    // Opposite s: (b, a, r), r read from the star of a (the one before b) or else of b (the
    // one after a).
    uint ia = uint(site_info[a].x), ib = uint(site_info[b].x);
    bool from_a = !star_deferred(ia);
    int o = from_a ? a : b;
    uint io = from_a ? ia : ib;
    int r = -1;
    if (from_a || !star_deferred(ib)) {
      StarRow ro = load_row(o);
      int p = star_find(ro, io, from_a ? b : a);
      bool inside = from_a ? (p > 0 || star_closed(io)) : (p < star_degree(io) - 1 || star_closed(io));
      if (p >= 0 && inside) r = star_at(ro, io, from_a ? p - 1 : p + 1);
    } else {
      uint at = atomicAdd(counters[COUNTER_UNRESOLVED], 1u);
      if (int(at) < params.unresolved_capacity) unresolved[int(at)] = 3 * at_out;
      else atomicAdd(counters[COUNTER_UNRESOLVED_OVERFLOW], 1u);
    }
    int across_ab = r >= 0 ? triangle_index(b, a, r) : -1;
    // Opposite a: (s, b, next); opposite b: (s, previous, a).
    int across_bs = (closed || t + 2 < deg) ? triangle_index(s, b, star_at(row, info, t + 2)) : -1;
    int across_sa = (closed || t >= 1) ? triangle_index(s, star_at(row, info, t - 1), a) : -1;
    neighbors[3 * at_out] = across_ab;
    neighbors[3 * at_out + 1] = across_bs;
    neighbors[3 * at_out + 2] = across_sa;
    ++at_out;
  }
  // Canary for lavapipe's loop cap (see star.comp): if it was reached, loops above may have
  // been cut short, and the host discards the whole adjacency.
  int canary = 0;
  for (int i = 0; i < min(params.site_count, 2); ++i) ++canary;
  if (canary != 2) atomicAdd(counters[COUNTER_LINKS_CUT], 1u);
}
