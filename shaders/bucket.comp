#version 450
// Sites sorted into the star grid's cells on the device (the CUDA backend does the same with
// CUB: cell keys, radix sort, gather, cell starts). The host uploads the sites and the hull's
// predecessors in SiteSet order and nothing else; a few passes, selected by params.pass, make
// what star.comp reads:
//
//   BUCKET_PASS_COUNT        cell of every site; cell sizes counted into cell_start[c + 1] (atomics)
//   (scan.comp)       inclusive scan of cell_start: cell c's sites are [start[c], start[c+1])
//   BUCKET_PASS_SCATTER      each site claims a slot of its cell (atomics: any order)
//   BUCKET_PASS_ORDER        each slot ranks its site among its cell's sites by SiteSet id and moves
//                     it there: within a cell the sites keep their SiteSet order, exactly as
//                     the host's counting sort leaves them, so the sorted ids, the stars'
//                     owners and the output do not depend on the atomics' order
//   BUCKET_PASS_PREDECESSOR  the hull predecessors, renumbered to sorted ids
//   BUCKET_PASS_RESTORE      after star.comp: the triangles' sorted ids back to SiteSet ids, checked,
//                     so the host copies the triangles as they are
//
// Ranking costs a cell's size per site. A cell of more than MAX_CELL sites (a crowded cluster)
// is reported in counters[COUNTER_CROWDED_CELL] instead: lavapipe silently leaves loops after 65535 iterations, and
// the host then buckets the sites itself.
#extension GL_ARB_gpu_shader_fp64 : enable
#extension GL_GOOGLE_include_directive : require

#include "host_device.h"

layout(local_size_x_id = 0) in;
layout(constant_id = BUCKET_SPEC_MAX_CELL) const int MAX_CELL = 4096;
// Quantile cells (quantile_cells.glsl) instead of uniform ones, as star.comp's.
layout(constant_id = BUCKET_SPEC_QUANTILE_CELLS) const bool QUANTILE_CELLS = false;


layout(std430, set = 0, binding = 0) readonly buffer InputSites { dvec2 input_sites[]; };
layout(std430, set = 0, binding = 1) readonly buffer InputPredecessor { int input_predecessor[]; };
layout(std430, set = 0, binding = 2) buffer CellKey { int cell_key[]; };       // SiteSet id -> cell
layout(std430, set = 0, binding = 3) buffer CellStart { int cell_start[]; };   // cells^2 + 1
layout(std430, set = 0, binding = 4) buffer Cursor { int cursor[]; };          // next free slot per cell
layout(std430, set = 0, binding = 5) buffer Unordered { int unordered[]; };    // slot -> SiteSet id
layout(std430, set = 0, binding = 6) writeonly buffer SortedSites { dvec2 sorted_sites[]; };
layout(std430, set = 0, binding = 7) buffer ToSite { int to_site[]; };         // sorted id -> SiteSet id
layout(std430, set = 0, binding = 8) buffer ToSorted { int to_sorted[]; };     // SiteSet id -> sorted id
layout(std430, set = 0, binding = 9) writeonly buffer Predecessor { int predecessor[]; };
layout(std430, set = 0, binding = 10) buffer Triangles { int triangles[]; };
// star.comp's counters; [0] triangles written; [8] a cell too crowded to rank; [9] a triangle
// with an invalid site id
layout(std430, set = 0, binding = 11) buffer Counters { uint counters[]; };
// Quantile cells' boundaries (unused with uniform cells).
layout(std430, set = 0, binding = 12) readonly buffer CellBounds { double cell_bounds[]; };

layout(push_constant) uniform Push { BucketParams params; };

#include "cells.glsl"
#include "quantile_cells.glsl"

void main() {
  const int i = params.first + int(gl_GlobalInvocationID.x);
  if (params.pass == BUCKET_PASS_RESTORE) {
    // Only the triangles star.comp wrote (it counts past the capacity when it overflows).
    const int written = int(min(counters[COUNTER_TRIANGLES], uint(params.triangle_capacity)));
    if (i >= 3 * written) return;
    const int id = triangles[i];
    if (id < 0 || id >= params.count) {
      atomicAdd(counters[COUNTER_INVALID_ID], 1u);
      return;
    }
    triangles[i] = to_site[id];
    return;
  }
  if (i >= params.count) return;
  if (params.pass == BUCKET_PASS_COUNT) {
    const dvec2 p = input_sites[i];
    const int c =
        QUANTILE_CELLS
            ? quantile_cell(p.y, params.cells - 1, params.cells - 1) * params.cells + quantile_cell(p.x, 0, params.cells - 1)
            : cell_coord(p.y, params.origin.y, params.inv_width.y, params.cells) * params.cells +
                  cell_coord(p.x, params.origin.x, params.inv_width.x, params.cells);
    cell_key[i] = c;
    atomicAdd(cell_start[c + 1], 1);
  } else if (params.pass == BUCKET_PASS_SCATTER) {
    unordered[atomicAdd(cursor[cell_key[i]], 1)] = i;
  } else if (params.pass == BUCKET_PASS_ORDER) {
    const int site = unordered[i];
    const int c = cell_key[site];
    const int begin = cell_start[c], end = cell_start[c + 1];
    if (end - begin > MAX_CELL) {
      if (i == begin) atomicAdd(counters[COUNTER_CROWDED_CELL], 1u);
      return;
    }
    int rank = 0;
    for (int k = begin; k < end; ++k) rank += unordered[k] < site ? 1 : 0;
    const int at = begin + rank;
    to_site[at] = site;
    to_sorted[site] = at;
    sorted_sites[at] = input_sites[site];
  } else if (params.pass == BUCKET_PASS_PREDECESSOR) {
    const int p = input_predecessor[to_site[i]];
    predecessor[i] = p < 0 ? -1 : to_sorted[p];
  }
}
