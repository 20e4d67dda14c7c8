#version 450
// Per-site seeding (docs/algorithm.md, "GPU, per-site seeding"): every site walks its own star
// of Delaunay triangles around itself, stores the star (for star_links.comp, which derives the
// adjacency from the stars), and emits the triangles it owns (smallest site id) in star order.
#extension GL_ARB_gpu_shader_fp64 : enable
#extension GL_GOOGLE_include_directive : require

layout(local_size_x_id = 0) in;
// Star row length in star[]: a site whose star has more neighbours defers to the seam stage
// (uniform inputs reach degree 17 about once in 10^6 sites). Only used in index arithmetic.
layout(constant_id = 1) const int STAR_CAPACITY = 16;
// Loop iterations one invocation may spend before deferring its site (see grid.glsl).
layout(constant_id = 2) const int LOOP_BUDGET = 1000000000;

layout(std430, set = 0, binding = 0) readonly buffer Sites { dvec2 sites[]; };
layout(std430, set = 0, binding = 1) readonly buffer CellStart { int cell_start[]; };
layout(std430, set = 0, binding = 2) readonly buffer Predecessor { int predecessor[]; };
layout(std430, set = 0, binding = 3) writeonly buffer Triangles { int triangles[]; };
// [0] triangles written, [1] deferred sites, [2] output overflow, [3] impossible searches
layout(std430, set = 0, binding = 4) buffer Counters { uint counters[]; };
// Row s: the star of s, counter-clockwise from index star_start, wrapping (star_common.glsl).
layout(std430, set = 0, binding = 5) buffer Star { int star[]; };
// [2s] star info (degree, start, closed / deferred bits), [2s + 1] first output triangle of s.
layout(std430, set = 0, binding = 6) writeonly buffer SiteInfo { int site_info[]; };

layout(push_constant) uniform Params {
  dvec2 origin;
  dvec2 inv_width;
  int cells;
  int site_count;
  int first_site;      // dispatches are split to respect maxComputeWorkGroupCount
  int triangle_capacity;
} params;

dvec2 site_at(int id) { return sites[id]; }
int cell_begin(int cell) { return cell_start[cell]; }
int slot_site(int slot) { return slot; }  // sites are stored sorted by cell

#include "grid.glsl"
#include "star_common.glsl"

void defer_site(int s) {
  site_info[2 * s] = int(STAR_DEFERRED);
  site_info[2 * s + 1] = -1;
  atomicAdd(counters[1], 1u);
}

void main() {
  int s = params.first_site + int(gl_GlobalInvocationID.x);
  if (s >= params.site_count) return;
  loop_budget = LOOP_BUDGET;

  Grid g;
  g.origin = params.origin;
  g.inv_width = params.inv_width;
  g.cells = params.cells;
  g.lo = ivec2(0);
  g.hi = ivec2(params.cells - 1);
  g.cell_base = 0;

  int v0;
  int slot;
  int status = nearest_search(g, s, v0, slot);
  if (status != SEARCH_FOUND) {
    if (status != SEARCH_DEFER) atomicAdd(counters[3], 1u);
    defer_site(s);
    return;
  }

  // The star goes straight into row s of star[]: the counter-clockwise walk from index 0 up,
  // the clockwise one (if the walk meets the hull) from the row's end down, so that the row read
  // from index (STAR_CAPACITY - m) on, wrapping, is the whole star counter-clockwise.
  int row = s * STAR_CAPACITY;
  dvec2 ps = sites[s];
  star[row] = v0;
  int deg = 1;
  int m = 0;

  // Counter-clockwise around s: triangle (s, v, apex(s->v)).
  int v = v0;
  bool closed = false;
  while (predecessor[s] != v) {
    --loop_budget;
    int c;
    status = apex_search(g, s, v, ps, sites[v], c, slot);
    if (status != SEARCH_FOUND) {
      if (status == SEARCH_NONE || status == SEARCH_OUTSIDE) atomicAdd(counters[3], 1u);
      defer_site(s);
      return;
    }
    if (c == v0) {
      closed = true;
      break;
    }
    if (deg >= STAR_CAPACITY) {
      defer_site(s);
      return;
    }
    star[row + deg] = c;
    ++deg;
    v = c;
  }
  if (!closed) {
    // The walk met the hull: the rest of the star lies clockwise from v0,
    // triangles (v, s, apex(v->s)).
    v = v0;
    while (predecessor[v] != s) {
      --loop_budget;
      int c;
      status = apex_search(g, v, s, sites[v], ps, c, slot);
      if (status != SEARCH_FOUND || c == v0) {
        if (status == SEARCH_NONE || status == SEARCH_OUTSIDE) atomicAdd(counters[3], 1u);
        defer_site(s);
        return;
      }
      if (deg + m >= STAR_CAPACITY) {
        defer_site(s);
        return;
      }
      star[row + STAR_CAPACITY - 1 - m] = c;
      ++m;
      v = c;
    }
  }
  deg += m;
  uint info = uint(deg) | (uint((STAR_CAPACITY - m) % STAR_CAPACITY) << 8) |
              (closed ? STAR_CLOSED : 0u);
  int tris = closed ? deg : deg - 1;
  int owned = 0;
  for (int t = 0; t < tris; ++t) {
    int a = star_at_row(row, info, t), b = star_at_row(row, info, t + 1);
    if (s < a && s < b) ++owned;
  }

  // Canary for lavapipe's loop cap: once it is reached every loop runs at most once, so a
  // two-trip loop that trips once means some search above may have been cut short.
  int canary = 0;
  for (int i = 0; i < min(params.site_count, 2); ++i) ++canary;
  if (canary != 2 || loop_budget < 0) {
    defer_site(s);
    return;
  }
  site_info[2 * s] = int(info);
  site_info[2 * s + 1] = -1;
  if (owned == 0) return;
  uint at = atomicAdd(counters[0], uint(owned));
  if (int(at) + owned > params.triangle_capacity) {
    atomicAdd(counters[2], 1u);
    return;
  }
  site_info[2 * s + 1] = int(at);
  // In star order: star_links.comp numbers a site's triangles the same way.
  int write_at = 3 * int(at);
  for (int t = 0; t < tris; ++t) {
    int a = star_at_row(row, info, t), b = star_at_row(row, info, t + 1);
    if (!(s < a && s < b)) continue;
    triangles[write_at] = s;
    triangles[write_at + 1] = a;
    triangles[write_at + 2] = b;
    write_at += 3;
  }
}
