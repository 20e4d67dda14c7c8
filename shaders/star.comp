#version 450
// Per-site seeding (docs/algorithm.md, "GPU, per-site seeding"): every site walks its own star
// of Delaunay triangles around itself, stores the star (for star_links.comp, which derives the
// adjacency from the stars), and emits the triangles it owns (smallest site id) in star order.
// The sites walk in passes, a class of ids at a time (params.pass); a walk reads every triangle
// it shares with a site of an earlier class from that site's star instead of searching for it.
//
// Shape of the code. The searches are written for two very different executors: GPU warps,
// and Mesa's lavapipe, which runs 8 invocations as the lanes of CPU vector registers and
// predicates every `if` — both sides of every branch run, masked, on every pass through the
// enclosing loop, and every storage-buffer access is a loop over the lanes. So the loops are
// nested by how often their bodies run:
//   candidate loop (innermost): one candidate site; floating-point filters only;
//   scan loop:              the next row segment of cells (the candidates' range);
//   search loop:            once a box of cells has been scanned: the empty-circle region of
//                           the best candidate, the next box, or the next edge of the walk
//                           (the steps that earlier passes' stars tell, in a loop of their own);
//   exact loop (outermost): once per candidate the filters could not decide (rare): the exact
//                           certificate and CGAL's perturbation, then back into the scan.
// The rare exact code thus costs lavapipe once per site, not once per candidate.
//
// A search visits boxes of cells. Cells are sorted row-major, so one row of a box is one
// contiguous range of sites: a box costs its rows, however many cells they hold. The first
// box covers a guess of the empty circle; each further box covers the region the best
// candidate's circle leaves (circle ∩ left half-plane, with a proven floating-point margin),
// which only shrinks as better candidates appear. The search ends when the region lies in the
// cells visited.
#extension GL_ARB_gpu_shader_fp64 : enable
#extension GL_GOOGLE_include_directive : require

layout(local_size_x_id = 0) in;
// Most neighbours a star may have (at most 16, the row length, see star_common.glsl): a site
// whose star has more defers to the seam stage (uniform inputs reach degree 17 about once in
// 10^6 sites).
layout(constant_id = 1) const int STAR_CAPACITY = 16;
// Loop iterations one invocation may spend before deferring its site. On lavapipe the backend
// keeps 8 lanes x budget under its cap of 65535 back-edges per batch (see the canary below).
layout(constant_id = 2) const int LOOP_BUDGET = 1000000000;
// The candidate loop's filters: in the edge's frame (predicates.glsl's apex filters, about half
// the arithmetic: lavapipe's star shader -7% at 1M uniform), or orient2d_filter and
// incircle_filter on the points (the H100's driver: 80 ms against 85 with the apex filters at
// 4096^2). Both decide the same signs or none; the exact path is the same.
layout(constant_id = 3) const bool APEX_FILTERS = true;
// The sites are a small integer lattice on which the apex filters' arithmetic is exact
// (engine/src/predicates/exact_lattice.hpp): every candidate is decided in the scan, ties by
// id (distances) and CGAL's perturbation (cocircular), instead of in the exact loop.
layout(constant_id = 4) const bool EXACT_LATTICE = false;
// Quantile cells (quantile_cells.glsl, for clustered and heavy-tailed inputs) instead of
// uniform ones (cells.glsl); the host chooses (star_cells.cpp).
layout(constant_id = 5) const bool QUANTILE_CELLS = false;
// The light first pass on GPUs (one class): no exact path. A walk that meets a candidate the
// filters cannot decide stops and marks its site STAR_HANDED_ON; a second dispatch (RETRY)
// walks only those sites, with the exact path. Inlined, the exact code's registers set the
// whole shader's: without it, the retry included, the star shader took 79.2 -> 70.2 ms at
// 4096^2 uniform and 169.6 -> 132.2 kuzmin on the H100's driver (session 11, call 16; the
// same deferrals). Classes (CPU devices) keep the exact path in every pass.
layout(constant_id = 6) const bool EXACT_PATH = true;
layout(constant_id = 7) const bool RETRY = false;
// The exact path also tries incircle_exact_differences (predicates.glsl), which decides nearly
// cocircular float inputs (decimal grids) that the certificate leaves to the seam stage. Only in
// the GPU's retry dispatch: inlined into a pass that every site takes, its expansion would cost
// that pass registers (lavapipe's classes leave such sites to the seam stage, which is the CPU
// there anyway).
layout(constant_id = 8) const bool EXACT_DIFFERENCES = false;
// The grid's outer ring of cells apart (one class, a device of our own): 1 walks only the sites
// of those cells, 2 all but them, 0 every site. The ring holds the hull-hugging sites whose walks
// are the longest by far; dispatched first, with no barrier before the rest's dispatch, they
// run beside it instead of ending the pass (the CUDA backend's edge stream, in one queue).
layout(constant_id = 9) const int EDGE_PART = 0;


// Sites, cell starts and hull predecessors are read as uniform texel buffers: on lavapipe a
// texel fetch is a vector gather, where a storage-buffer load is a loop over the lanes.
layout(set = 0, binding = 0) uniform usamplerBuffer site_texels;   // RGBA32UI: one dvec2
layout(set = 0, binding = 1) uniform isamplerBuffer cell_texels;   // R32I
layout(set = 0, binding = 2) uniform isamplerBuffer predecessor_texels;  // R32I: hull.predecessor
layout(std430, set = 0, binding = 3) writeonly buffer Triangles { int triangles[]; };
// [0] triangles written, [1] deferred sites, [2] output overflow, [3] impossible searches
layout(std430, set = 0, binding = 4) buffer Counters { uint counters[]; };
// Row s (four ivec4): the star of s, counter-clockwise from index star_start, wrapping
// (star_common.glsl). Written only for sites that do not defer.
layout(std430, set = 0, binding = 5) buffer Star { ivec4 star4[]; };
// The same rows as words: until a site of a later pass walks, its row holds what the stars of
// earlier passes posted to it (the count in site_info_words, below).
layout(std430, set = 0, binding = 5) buffer StarWords { int star_words[]; };
// Site s: (star info (star_common.glsl), first output triangle of s or -1).
layout(std430, set = 0, binding = 6) buffer SiteInfo { ivec2 site_info[]; };
// The same words: word 2u + 1 of a site u of a later pass counts the posts of earlier passes
// to u's row, minus one (the host fills the words with -1 before the first pass; only finished
// stars post).
layout(std430, set = 0, binding = 6) buffer SiteInfoWords { int site_info_words[]; };
// Quantile cells' boundaries (unused with uniform cells).
layout(std430, set = 0, binding = 7) readonly buffer CellBounds { double cell_bounds[]; };

layout(push_constant) uniform Params {
  dvec2 origin;
  dvec2 inv_width;
  int cells;
  int site_count;
  int first_site;      // dispatches are split to respect maxComputeWorkGroupCount
  int triangle_capacity;
  // A scan of more cells than this stops at the first better candidate, to plan a smaller box.
  int big_scan_cells;
  // Passes (docs/algorithm.md, "Passes"): the sites are split into pass_mask + 1 classes by
  // their ids (runs of 2^pass_shift consecutive ids in turn), walked class by class; this
  // dispatch walks class `pass`. A site takes every triangle it shares with a site of an
  // earlier class from that site's star, and searches only for the rest.
  int pass;
  int pass_mask;  // classes - 1, a power of two minus one; 0: one pass
  int pass_shift;
} params;

int class_of(int u) { return (u >> params.pass_shift) & params.pass_mask; }

dvec2 site_at(int i) {
  uvec4 u = texelFetch(site_texels, i);
  return dvec2(packDouble2x32(u.xy), packDouble2x32(u.zw));
}
int cell_start_at(int c) { return texelFetch(cell_texels, c).x; }
int predecessor_of(int s) { return texelFetch(predecessor_texels, s).x; }

#include "cells.glsl"
#include "predicates.glsl"
#include "quantile_cells.glsl"
#include "star_common.glsl"

// What the stars of earlier passes tell a site s, posted into its row by each finished star w
// of an earlier class that has s in it (at most POSTS_MAX; the rest are dropped and searched
// for): w, and the neighbours of s just before and after w counter-clockwise around s (-1 where
// w's star does not tell: w met the hull). So a walk step s->v has a known apex where v is
// posted (the one after v) or where some posted w comes just after v (w itself).
const int POSTS_MAX = 5;  // triples in a 16-word row
struct Earlier {
  ivec4 w0, w1, before0, before1, after0, after1;
};

// The entry of `values` where `keys` holds k (keys hold distinct sites or -1), or -1.
int pick_where(ivec4 k0, ivec4 k1, ivec4 v0, ivec4 v1, int k) {
  ivec4 m0 = mix(ivec4(-1), v0, equal(k0, ivec4(k)));
  ivec4 m1 = mix(ivec4(-1), v1, equal(k1, ivec4(k)));
  ivec4 m = max(m0, m1);
  return max(max(m.x, m.y), max(m.z, m.w));
}

// The apex of s->v (counter-clockwise) or of v->s (clockwise) where earlier stars tell it, or -1.
int known_apex(Earlier e, int v, bool counter_clockwise) {
  if (v < 0) return -1;
  int from_v = counter_clockwise ? pick_where(e.w0, e.w1, e.after0, e.after1, v)
                                 : pick_where(e.w0, e.w1, e.before0, e.before1, v);
  int next = counter_clockwise ? pick_where(e.before0, e.before1, e.w0, e.w1, v)
                               : pick_where(e.after0, e.after1, e.w0, e.w1, v);
  return from_v >= 0 ? from_v : next;
}

const int PHASE_NEAREST = 0;  // nearest neighbour v0 of s
const int PHASE_CCW = 1;      // triangles (s, v, apex(s->v)) counter-clockwise from v0
const int PHASE_CW = 2;       // the walk met the hull: (v, s, apex(v->s)) clockwise from v0
const int PHASE_DONE = 3;
const int PHASE_DEFER = 4;

const int NONE_BELOW = 1 << 29;  // an empty box: lo = NONE_BELOW, hi = -NONE_BELOW
// The nearest-neighbour search starts with the cells within this many cell widths of s (counted
// on 200k uniform and gaussian sites: 9.4 candidates per site, where the 3x3 cells took 18.6).
const double NN_REACH = 0.5lf;

ivec2 cell_of(dvec2 p) {
  if (QUANTILE_CELLS)
    return ivec2(quantile_cell(p.x, 0, params.cells - 1), quantile_cell(p.y, params.cells - 1, params.cells - 1));
  return ivec2(cell_coord(p.x, params.origin.x, params.inv_width.x, params.cells),
               cell_coord(p.y, params.origin.y, params.inv_width.y, params.cells));
}


int box_cells(ivec2 lo, ivec2 hi) {
  ivec2 size = max(hi - lo + 1, ivec2(0));
  return size.x * size.y;
}

bool box_inside(ivec2 lo, ivec2 hi, ivec2 outer_lo, ivec2 outer_hi) {
  return all(greaterThanEqual(lo, outer_lo)) && all(lessThanEqual(hi, outer_hi));
}

// Cell box of circle(a, b, c) ∩ left half-plane of a->b, for c strictly left of a->b; the whole
// grid when the circle is too ill-conditioned to bound in floating point.
//
// Why the margin holds: a centre is computed only when the angle at a has sin >= 1e-4
// (cross^2 >= 1e-8 |ba|^2 |ca|^2). Then the denominator 2 cross has relative error <= 3 eps /
// 1e-4, and the numerators' absolute errors are <= 5 eps (|ba| + |ca|) |ba| |ca|, so the
// computed centre is off by < 1e-11 (|ba| + |ca| + R); input rounding of ba, ca (relative eps)
// moves it by the same order. The margin 1e-6 (R + |ba|_1 + |ca|_1) (1-norms bound the lengths
// from above) exceeds that by five orders of magnitude, and also covers sqrt and division that
// are not correctly rounded on some devices. The absolute part covers rounding of the centre
// and extreme points themselves: sites are scaled below 1 in magnitude.
void apex_region(dvec2 a, dvec2 b, dvec2 c, out ivec2 lo_cell, out ivec2 hi_cell) {
  precise dvec2 ba = b - a;
  precise dvec2 ca = c - a;
  precise double cross = ba.x * ca.y - ba.y * ca.x;
  precise double b2 = ba.x * ba.x + ba.y * ba.y;
  precise double c2 = ca.x * ca.x + ca.y * ca.y;
  double lb = sqrt(b2);
  lo_cell = ivec2(0);
  hi_cell = ivec2(params.cells - 1);
  if (cross > 0.0lf && cross * cross >= 1.0e-8lf * b2 * c2) {
    precise double inv = 0.5lf / cross;
    precise double ux = (ca.y * b2 - ba.y * c2) * inv;
    precise double uy = (ba.x * c2 - ca.x * b2) * inv;
    dvec2 centre = a + dvec2(ux, uy);
    double radius = sqrt(ux * ux + uy * uy);
    double margin = 1.0e-6lf * (radius + abs(ba.x) + abs(ba.y) + abs(ca.x) + abs(ca.y)) + ABS_MARGIN;
    dvec2 lo = min(a, b), hi = max(a, b);
    // Extreme points of the circle count only if they can be on the left of a->b.
    double tol = 2.0lf * margin * lb;
    double rx = radius * ba.y, ry = radius * ba.x;  // cross(ba, ±radius e_k) terms
    double side = ba.x * (centre.y - a.y) - ba.y * (centre.x - a.x);
    if (side - rx >= -tol) { lo.x = min(lo.x, centre.x + radius); hi.x = max(hi.x, centre.x + radius); }
    if (side + rx >= -tol) { lo.x = min(lo.x, centre.x - radius); hi.x = max(hi.x, centre.x - radius); }
    if (side + ry >= -tol) { lo.y = min(lo.y, centre.y + radius); hi.y = max(hi.y, centre.y + radius); }
    if (side - ry >= -tol) { lo.y = min(lo.y, centre.y - radius); hi.y = max(hi.y, centre.y - radius); }
    lo_cell = cell_of(lo - dvec2(margin));
    hi_cell = cell_of(hi + dvec2(margin));
  } else {
    // Too flat to locate the centre. If c sees a-b at an obtuse angle, the region is the minor
    // segment, and every point x in it sees a-b at an angle >= angle(a c b) > 90 degrees: it
    // lies in the disc with diameter a-b (Thales), which needs no centre. Hull-hugging flat
    // triangles of uniform inputs are exactly this case.
    precise dvec2 ac = a - c;
    precise dvec2 bc = b - c;
    precise double dot_c = ac.x * bc.x + ac.y * bc.y;
    precise double l2ac = ac.x * ac.x + ac.y * ac.y;
    precise double l2bc = bc.x * bc.x + bc.y * bc.y;
    if (dot_c < 0.0lf && dot_c * dot_c > 1.0e-12lf * l2ac * l2bc) {
      dvec2 mid = 0.5lf * (a + b);
      double radius_t = 0.5lf * lb * (1.0lf + 1.0e-6lf) + 1.0e-6lf * lb + ABS_MARGIN;
      lo_cell = cell_of(mid - dvec2(radius_t));
      hi_cell = cell_of(mid + dvec2(radius_t));
    }
  }
}

void main() {
  int i = params.first_site + int(gl_GlobalInvocationID.x);
  int run = i >> params.pass_shift;
  int s = ((run * (params.pass_mask + 1) + params.pass) << params.pass_shift) + (i - (run << params.pass_shift));
  if (s >= params.site_count) return;
  if (RETRY && uint(site_info[s].x) != STAR_HANDED_ON) return;
  if (EDGE_PART != 0) {
    const ivec2 c = cell_of(site_at(s));
    const bool edge = min(min(c.x, c.y), min(params.cells - 1 - c.x, params.cells - 1 - c.y)) < 1;
    if (edge != (EDGE_PART == 1)) return;
  }
  int budget = LOOP_BUDGET;
  ivec2 grid_hi = ivec2(params.cells - 1);
  dvec2 ps = site_at(s);
  int pred_s = predecessor_of(s);

  int phase = PHASE_NEAREST;
  bool impossible = false, handed_on = false;
  // The edge searched, a->b (for the nearest neighbour: a = b = s).
  int ia = s, ib = s;
  dvec2 pa = ps, pb = ps;
  // The edge in its own frame (B = b - a, |B|^2), for the apex filters.
  precise dvec2 edge = dvec2(0.0lf);
  precise double edge2 = 0.0lf;
  // Best candidate so far.
  int best = -1;
  dvec2 best_p = ps;
  double best_d2 = 0.0lf;
  // Boxes: visited (done), target (being scanned: target minus visited, row segment by row
  // segment; segment `part` 0 is left of the visited box or the whole row, 1 right of it).
  ivec2 vlo = ivec2(NONE_BELOW), vhi = ivec2(-NONE_BELOW);
  ivec2 tlo, thi;
  if (QUANTILE_CELLS) {  // cells of any width: the first box is the site's cell
    tlo = cell_of(ps);
    thi = tlo;
  } else {
    dvec2 nn_reach = NN_REACH / params.inv_width;  // inv_width > 0: the sites are not collinear
    tlo = cell_of(ps - nn_reach);
    thi = cell_of(ps + nn_reach);
  }
  int y = tlo.y - 1, part = 1, slot = 0, slot_end = 0;
  int pending = -1;
  bool big_scan = false, restart = false;
  // The neighbours of earlier passes, from the posts in s's row; the walk starts at the first of
  // them (no nearest-neighbour search).
  Earlier earlier = Earlier(ivec4(-1), ivec4(-1), ivec4(-1), ivec4(-1), ivec4(-1), ivec4(-1));
  bool known = false;
  if (params.pass > 0) {
    int posted = min(site_info_words[2 * s + 1] + 1, POSTS_MAX);
    StarRow inbox = StarRow(star4[4 * s], star4[4 * s + 1], star4[4 * s + 2], star4[4 * s + 3]);
    for (int k = 0; k < posted; ++k) {
      --budget;
      int before = row_pick(inbox, 3 * k), w = row_pick(inbox, 3 * k + 1), after = row_pick(inbox, 3 * k + 2);
      bvec4 at0 = equal(ivec4(k), ivec4(0, 1, 2, 3)), at1 = equal(ivec4(k), ivec4(4, 5, 6, 7));
      earlier.w0 = mix(earlier.w0, ivec4(w), at0);
      earlier.w1 = mix(earlier.w1, ivec4(w), at1);
      earlier.before0 = mix(earlier.before0, ivec4(before), at0);
      earlier.before1 = mix(earlier.before1, ivec4(before), at1);
      earlier.after0 = mix(earlier.after0, ivec4(after), at0);
      earlier.after1 = mix(earlier.after1, ivec4(after), at1);
    }
    int first = max(max(max(earlier.w0.x, earlier.w0.y), max(earlier.w0.z, earlier.w0.w)),
                    max(max(earlier.w1.x, earlier.w1.y), max(earlier.w1.z, earlier.w1.w)));
    if (first >= 0) {  // the walk starts at a posted neighbour
      best = first;
      best_p = site_at(first);
      known = true;
      y = thi.y;  // an empty scan
    }
  }
  // The walk. The star, in registers: counter-clockwise from index 0 up; clockwise (if the
  // walk meets the hull) from index 15 down, so that the row read from index 16 - m on,
  // wrapping, is the whole star counter-clockwise.
  StarRow row = StarRow(ivec4(-1), ivec4(-1), ivec4(-1), ivec4(-1));
  int v0 = -1, v = -1, deg = 0, m = 0;
  bool closed = false;

  for (;;) {    // exact loop
    for (;;) {  // search loop
      for (;;) {  // scan loop: row segments, and in each the candidates
        if (slot >= slot_end) {
          if (--budget < 0) break;
          // Next row segment of target minus visited.
          bool in_rows = y >= vlo.y && y <= vhi.y;
          if (part == 0 && in_rows) {
            part = 1;
          } else {
            part = 0;
            ++y;
          }
          if (y > thi.y) break;
          in_rows = y >= vlo.y && y <= vhi.y;
          int x0 = (in_rows && part == 1) ? vhi.x + 1 : tlo.x;
          int x1 = (in_rows && part == 0) ? vlo.x - 1 : thi.x;
          slot = 0;
          slot_end = 0;
          if (x0 <= x1) {
            int c0 = y * params.cells + x0;
            slot = cell_start_at(c0);
            slot_end = cell_start_at(c0 + (x1 - x0) + 1);
          }
        }
        for (; slot < slot_end; ++slot) {  // candidate loop: straight-line, one exit
          if (--budget < 0) break;
          int ip = slot;  // sites are stored sorted by cell
          dvec2 p = site_at(ip);
          dvec3 q = apex_point(pa, p);  // in the nearest-neighbour search a = s: q.z = |p - s|^2
          // The best's lift is formed again for each candidate: kept in the loop instead, its six
          // doubles cost lavapipe more than the operations (1M uniform: star shader 722-735 ms
          // formed again, 769-777 kept, 795-800 with the full filters; H100: 91 ms kept).
          int o = APEX_FILTERS ? apex_orient_filter(apex_lift(edge, edge2, q)) : orient2d_filter(pa, pb, p);
          int ic = APEX_FILTERS ? apex_incircle_filter(apex_lift(edge, edge2, apex_point_with(pa, best_p, best_d2)), q)
                                : incircle_filter(pa, pb, best_p, p);
          double d2 = q.z;
          // 0: reject, 1: better than the best, 2: the filters cannot tell. A restart may
          // visit best again; a, b (or s) are never candidates.
          int verdict = phase == PHASE_NEAREST
                            ? ((best < 0 || d2 < best_d2 * (1.0lf - 1.0e-12lf)) ? 1
                               : (d2 > best_d2 * (1.0lf + 1.0e-12lf) ? 0 : 2))
                            : (o == -1 ? 0 : (o == UNCERTAIN ? 2 : (best < 0 ? 1 : (ic == -1 ? 0 : ic))));
          if (EXACT_LATTICE) {
            ApexLift lift = apex_lift(edge, edge2, q);  // lift.k: orient2d(a, b, p), exact
            double value = apex_incircle_value(apex_lift(edge, edge2, apex_point(pa, best_p)), q);
            int tie = value == 0.0lf && lift.k > 0.0lf && best >= 0 ? cocircular_perturbed_lattice(pa, pb, best_p, p) : 0;
            verdict = phase == PHASE_NEAREST
                          ? ((best < 0 || d2 < best_d2 || (d2 == best_d2 && ip < best)) ? 1 : 0)
                          : (lift.k <= 0.0lf ? 0
                             : best < 0      ? 1
                             : value > 0.0lf ? 1
                             : value < 0.0lf ? 0
                             : tie == UNCERTAIN ? 2 : (tie > 0 ? 1 : 0));
          }
          if (ip == ia || ip == ib || ip == best) verdict = 0;
          bool better = verdict == 1;
          best = better ? ip : best;
          best_p = better ? p : best_p;
          best_d2 = better ? d2 : best_d2;
          // Leave to decide exactly, or, when a large box was planned from a worse
          // candidate's region, to plan again.
          if (verdict == 2 || (better && big_scan)) {
            pending = verdict == 2 ? ip : -1;
            restart = better;
            break;
          }
        }
        if (budget < 0 || pending >= 0 || restart) break;
      }
      if (budget < 0 || pending >= 0) break;

      // The target box is scanned (or abandoned for a better plan: restart).
      if (!restart) {
        vlo = tlo;
        vhi = thi;
      }
      restart = false;
      bool found = known;
      known = false;
      if (found) {
        // Nothing to plan.
      } else if (best < 0) {
        if (vlo == ivec2(0) && vhi == grid_hi) {
          impossible = true;  // no candidate anywhere: cannot happen for a valid hull
          phase = PHASE_DEFER;
          break;
        }
        ivec2 grow = max(vhi - vlo + 1, ivec2(1));
        tlo = max(vlo - grow, ivec2(0));
        thi = min(vhi + grow, grid_hi);
      } else {
        ivec2 rlo, rhi;
        if (phase == PHASE_NEAREST) {
          double reach = sqrt(best_d2) * (1.0lf + 1.0e-6lf) + ABS_MARGIN;
          rlo = cell_of(ps - dvec2(reach));
          rhi = cell_of(ps + dvec2(reach));
        } else {
          apex_region(pa, pb, best_p, rlo, rhi);
        }
        found = box_inside(rlo, rhi, vlo, vhi);
        // Towards the region, but by at most half the visited box per side: nearer candidates
        // come first and shrink the region (a far region is often a poor early candidate's).
        if (vlo.x > vhi.x) {
          // Restarted in a search's first box: the region within that box.
          tlo = max(rlo, tlo);
          thi = min(rhi, thi);
        } else {
          ivec2 reach = max((vhi - vlo + 1) >> 1, ivec2(1));
          tlo = max(min(vlo, rlo), vlo - reach);
          thi = min(max(vhi, rhi), vhi + reach);
        }
      }
      y = tlo.y - 1;
      part = 1;
      slot = 0;
      slot_end = 0;
      big_scan = box_cells(tlo, thi) - box_cells(vlo, vhi) > params.big_scan_cells;
      if (!found) continue;

      // The search is over: best is the answer. Take the walk's next step, and the steps after
      // it that neighbours of earlier passes have taken already (their stars hold them).
      int c = best;
      for (;;) {
        if (phase == PHASE_NEAREST) {
          v0 = c;
          row_put(row, 0, c);
          deg = 1;
          v = c;
          phase = PHASE_CCW;
        } else if (phase == PHASE_CCW) {
          if (c == v0) {
            closed = true;
            phase = PHASE_DONE;
          } else if (deg >= STAR_CAPACITY) {
            phase = PHASE_DEFER;
          } else {
            row_put(row, deg, c);
            ++deg;
            v = c;
          }
        } else {
          if (c == v0 || deg + m >= STAR_CAPACITY) {
            phase = PHASE_DEFER;
          } else {
            row_put(row, STAR_ROW - 1 - m, c);
            ++m;
            v = c;
          }
        }
        if (phase == PHASE_CCW && pred_s == v) {
          phase = PHASE_CW;  // s->v is an outer edge: the rest lies clockwise from v0
          v = v0;
        }
        if (phase == PHASE_CW && predecessor_of(v) == s) phase = PHASE_DONE;
        if (phase >= PHASE_DONE || --budget < 0) break;
        c = known_apex(earlier, v, phase == PHASE_CCW);
        if (c < 0) break;
      }
      if (phase >= PHASE_DONE || budget < 0) break;
      // Search the next edge: s->v counter-clockwise, v->s clockwise.
      dvec2 pv = site_at(v);
      ia = phase == PHASE_CCW ? s : v;
      ib = phase == PHASE_CCW ? v : s;
      pa = phase == PHASE_CCW ? ps : pv;
      pb = phase == PHASE_CCW ? pv : ps;
      edge = pb - pa;
      edge2 = edge.x * edge.x + edge.y * edge.y;
      best = -1;
      vlo = ivec2(NONE_BELOW);
      vhi = ivec2(-NONE_BELOW);
      // First box: half-width |ab|_1 / 2 around the point |ab| / 2 left of the midpoint, a guess
      // at where the empty circle lies (tuned on uniform inputs; any box is correct).
      dvec2 ba = pb - pa;
      dvec2 centre = 0.5lf * (pa + pb) + 0.5lf * dvec2(-ba.y, ba.x);
      double r = 0.5lf * (abs(ba.x) + abs(ba.y));
      tlo = cell_of(centre - dvec2(r));
      thi = cell_of(centre + dvec2(r));
      y = tlo.y - 1;
      big_scan = box_cells(tlo, thi) > params.big_scan_cells;
    }
    if (budget < 0) phase = PHASE_DEFER;
    if (phase >= PHASE_DONE) break;
    if (!EXACT_PATH) {
      handed_on = true;
      phase = PHASE_DEFER;
      break;
    }

    // Decide the pending candidate exactly, then resume the scan after it.
    int ip = pending;
    dvec2 p = site_at(ip);
    int verdict = 0;
    if (phase == PHASE_NEAREST) {
      bool ok = true;
      double e_new = squared_distance_certified(p, ps, ok);
      double e_old = squared_distance_certified(best_p, ps, ok);
      verdict = !ok ? 2 : (e_new < e_old ? 1 : 0);
      if (!ok && EXACT_DIFFERENCES) {
        int cmp = compare_distance_exact_differences(ps, p, best_p);
        verdict = cmp == UNCERTAIN ? 2 : (cmp < 0 ? 1 : 0);
      }
    } else {
      int o = orient2d_device(pa, pb, p);
      if (o == UNCERTAIN && EXACT_DIFFERENCES) o = orient2d_exact_differences(pa, pb, p);
      if (o == UNCERTAIN) {
        verdict = 2;
      } else if (o > 0) {
        int sign = best < 0                ? 1
                   : EXACT_DIFFERENCES ? incircle_perturbed_exact_differences(pa, pb, best_p, p)
                                       : incircle_perturbed_device(pa, pb, best_p, p);
        verdict = sign == UNCERTAIN ? 2 : (sign > 0 ? 1 : 0);
      }
    }
    if (verdict == 2) {
      phase = PHASE_DEFER;
      break;
    }
    if (verdict == 1) {
      dvec3 q = apex_point(pa, p);
      best = ip;
      best_p = p;
      best_d2 = q.z;
    }
    slot = ip + 1;
    pending = -1;
  }

  // Canary for lavapipe's loop cap: once it is reached every loop runs at most once, so a
  // two-trip loop that trips once means some search above may have been cut short.
  int canary = 0;
  for (int i = 0; i < min(params.site_count, 2); ++i) ++canary;
  if (phase == PHASE_DEFER || canary != 2) {
    if (handed_on && canary == 2) {
      site_info[s] = ivec2(int(STAR_HANDED_ON), -1);
      return;
    }
    if (impossible) atomicAdd(counters[3], 1u);
    site_info[s] = ivec2(int(STAR_DEFERRED), -1);
    atomicAdd(counters[1], 1u);
    return;
  }

  deg += m;
  uint info = uint(deg) | (uint(m > 0 ? STAR_ROW - m : 0) << 5) | (closed ? STAR_CLOSED : 0u);
  int tris = closed ? deg : deg - 1;
  uint owned = 0u;
  int a = star_at(row, info, 0);
  for (int t = 0; t < tris; ++t) {
    int b = star_at(row, info, t + 1);
    if (s < a && s < b) owned |= 1u << uint(t);
    a = b;
  }
  info |= owned << 16;
  star4[4 * s] = row.q0;
  star4[4 * s + 1] = row.q1;
  star4[4 * s + 2] = row.q2;
  star4[4 * s + 3] = row.q3;
  int count = bitCount(owned);
  int at = -1;
  if (count > 0) {
    at = int(atomicAdd(counters[0], uint(count)));
    if (at + count > params.triangle_capacity) {
      atomicAdd(counters[2], 1u);
      at = -1;
    }
  }
  site_info[s] = ivec2(int(info), at);
  if (params.pass < params.pass_mask) {
    for (int t = 0; t < deg; ++t) {
      int u = star_at(row, info, t);
      if (class_of(u) > params.pass) {  // post to u's row (its count word starts at -1)
        int k = atomicAdd(site_info_words[2 * u + 1], 1) + 1;
        if (k < POSTS_MAX) {
          // The triangles (s, star t-1, u) and (s, u, star t+1): around u, s comes just after
          // star t+1 and just before star t-1.
          star_words[16 * u + 3 * k] = t + 1 < deg || closed ? star_at(row, info, t + 1) : -1;
          star_words[16 * u + 3 * k + 1] = s;
          star_words[16 * u + 3 * k + 2] = t > 0 || closed ? star_at(row, info, t - 1) : -1;
        }
      }
    }
  }
  if (at < 0) return;
  // In star order: star_links.comp numbers a site's triangles the same way.
  int write_at = 3 * at;
  for (uint left = owned; left != 0u; left &= left - 1u) {
    int t = findLSB(left);
    triangles[write_at] = s;
    triangles[write_at + 1] = star_at(row, info, t);
    triangles[write_at + 2] = star_at(row, info, t + 1);
    write_at += 3;
  }
}
