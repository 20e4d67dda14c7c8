#version 450
// Per-site seeding (docs/algorithm.md, "GPU, per-site seeding"): every site walks its own star
// of Delaunay triangles around itself, and emits the triangles it owns (smallest site id).
#extension GL_ARB_gpu_shader_fp64 : enable
#extension GL_GOOGLE_include_directive : require

layout(local_size_x_id = 0) in;
// Longest star a site walks before giving up and deferring to the seam stage.
layout(constant_id = 1) const int MAX_STAR_SPEC = 48;  // unused: see MAX_STAR
// Array sizes stay literal: arrays sized by specialization constants are a driver risk.
const int MAX_STAR = 48;
// Loop iterations one invocation may spend before deferring its site (see grid.glsl).
layout(constant_id = 2) const int LOOP_BUDGET = 1000000000;

layout(std430, set = 0, binding = 0) readonly buffer Sites { dvec2 sites[]; };
layout(std430, set = 0, binding = 1) readonly buffer CellStart { int cell_start[]; };
layout(std430, set = 0, binding = 2) readonly buffer Predecessor { int predecessor[]; };
layout(std430, set = 0, binding = 3) writeonly buffer Triangles { int triangles[]; };
// [0] triangles written, [1] deferred sites, [2] output overflow, [3] impossible searches
layout(std430, set = 0, binding = 4) buffer Counters { uint counters[]; };

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

void defer_site() { atomicAdd(counters[1], 1u); }

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
    defer_site();
    return;
  }

  // Owned triangles, stored as (s, x[k], y[k]) counter-clockwise.
  int own_x[MAX_STAR];
  int own_y[MAX_STAR];
  int owned = 0;
  dvec2 ps = sites[s];

  // Counter-clockwise around s: triangle (s, v, apex(s->v)).
  int v = v0;
  int steps = 0;
  bool closed = false;
  while (predecessor[s] != v) {
    --loop_budget;
    int c;
    status = apex_search(g, s, v, ps, sites[v], c, slot);
    if (status != SEARCH_FOUND || ++steps > MAX_STAR) {
      if (status == SEARCH_NONE || status == SEARCH_OUTSIDE) atomicAdd(counters[3], 1u);
      defer_site();
      return;
    }
    if (s < v && s < c) {
      own_x[owned] = v;
      own_y[owned] = c;
      ++owned;
    }
    v = c;
    if (v == v0) {
      closed = true;
      break;
    }
  }
  if (!closed) {
    // The walk met the hull: the rest of the star lies clockwise from v0,
    // triangles (v, s, apex(v->s)).
    v = v0;
    while (predecessor[v] != s) {
      --loop_budget;
      int c;
      status = apex_search(g, v, s, sites[v], ps, c, slot);
      if (status != SEARCH_FOUND || ++steps > MAX_STAR) {
        if (status == SEARCH_NONE || status == SEARCH_OUTSIDE) atomicAdd(counters[3], 1u);
        defer_site();
        return;
      }
      if (s < v && s < c) {
        own_x[owned] = c;
        own_y[owned] = v;
        ++owned;
      }
      v = c;
    }
  }

  // Canary for lavapipe's loop cap: once it is reached every loop runs at most once, so a
  // two-trip loop that trips once means some search above may have been cut short.
  int canary = 0;
  for (int i = 0; i < min(params.site_count, 2); ++i) ++canary;
  if (canary != 2 || loop_budget < 0) {
    defer_site();
    return;
  }
  if (owned == 0) return;
  uint at = atomicAdd(counters[0], uint(owned));
  if (int(at) + owned > params.triangle_capacity) {
    atomicAdd(counters[2], 1u);
    return;
  }
  for (int k = 0; k < owned; ++k) {
    int t = 3 * (int(at) + k);
    triangles[t] = s;
    triangles[t + 1] = own_x[k];
    triangles[t + 2] = own_y[k];
  }
}
