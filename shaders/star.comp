#version 450
// Per-site seeding (docs/algorithm.md, "GPU, per-site seeding"): every site walks its own star
// of Delaunay triangles around itself, stores the star (for star_links.comp, which derives the
// adjacency from the stars), and emits the triangles it owns (smallest site id) in star order.
// The sites walk in phases (params.phase); a walk reads every triangle it shares with a site of
// an earlier phase from what that site's star posted to its inbox instead of searching for it.
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
//                           (the steps that earlier phases' posts tell, in a loop of their own);
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

#include "host_device.h"

layout(local_size_x_id = STAR_SPEC_WORKGROUP) in;
// Most neighbours a star may have (at most STAR_ROW, the row length, host_device.h): a site
// whose star has more defers to the seam stage (uniform inputs reach degree 17 about once in
// 10^6 sites).
layout(constant_id = STAR_SPEC_CAPACITY) const int STAR_CAPACITY = 16;
// Loop iterations one invocation may spend before deferring its site. On lavapipe the backend
// keeps 8 lanes x budget under its cap of 65535 back-edges per batch (see the canary below).
layout(constant_id = STAR_SPEC_LOOP_BUDGET) const int LOOP_BUDGET = 1000000000;
// The candidate loop's filters: in the edge's frame (predicates.glsl's apex filters, about half
// the arithmetic: lavapipe's star shader -7% at 1M uniform), or orient2d_filter and
// incircle_filter on the points (the H100's driver: 80 ms against 85 with the apex filters at
// 4096^2). Both decide the same signs or none; the exact path is the same.
layout(constant_id = STAR_SPEC_APEX_FILTERS) const bool APEX_FILTERS = true;
// The sites are a small integer lattice on which the apex filters' arithmetic is exact
// (engine/src/predicates/exact_lattice.hpp): every candidate is decided in the scan, ties by
// id (distances) and CGAL's perturbation (cocircular), instead of in the exact loop.
layout(constant_id = STAR_SPEC_EXACT_LATTICE) const bool EXACT_LATTICE = false;
// Quantile cells (quantile_cells.glsl, for clustered and heavy-tailed inputs) instead of
// uniform ones (cells.glsl); the host chooses (star_cells.cpp).
layout(constant_id = STAR_SPEC_QUANTILE_CELLS) const bool QUANTILE_CELLS = false;
// The light first_pass on GPUs (one phase): no exact path. A walk that meets a candidate the
// filters cannot decide stops and marks its site STAR_HANDED_ON; a second dispatch, the retry
// (RETRY), walks only those sites, with the exact path. Inlined, the exact code's registers set
// the whole shader's: without it, the retry included, the star shader took 79.2 -> 70.2 ms at
// 4096^2 uniform and 169.6 -> 132.2 kuzmin on the H100's driver (2026-11-25; the same
// deferrals). Phases (CPU devices) keep the exact path in every dispatch.
layout(constant_id = STAR_SPEC_EXACT_PATH) const bool EXACT_PATH = true;
layout(constant_id = STAR_SPEC_RETRY) const bool RETRY = false;
// The exact path also tries incircle_exact_differences (predicates.glsl), which decides nearly
// cocircular float inputs (decimal grids) that the certificate leaves to the seam stage. Only in
// the GPU's retry dispatch: inlined into a pass that every site takes, its expansion would cost
// that pass registers (lavapipe's phases leave such sites to the seam stage, which is the CPU
// there anyway).
layout(constant_id = STAR_SPEC_EXACT_DIFFERENCES) const bool EXACT_DIFFERENCES = false;
// The grid's outer ring of cells apart (one phase, a device of our own): 1 walks only the sites
// of those cells, 2 all but them, 0 every site. The ring holds the hull-hugging sites whose walks
// are the longest by far; dispatched first, with no barrier before the rest's dispatch, they
// run beside it instead of ending the pass (the CUDA backend's edge stream, in one queue).
layout(constant_id = STAR_SPEC_EDGE_PART) const int EDGE_PART = 0;


// Sites, cell starts and hull predecessors are read as uniform texel buffers: on lavapipe a
// texel fetch is a vector gather, where a storage-buffer load is a loop over the lanes.
layout(set = 0, binding = 0) uniform usamplerBuffer site_texels;   // RGBA32UI: one dvec2
layout(set = 0, binding = 1) uniform isamplerBuffer cell_texels;   // R32I
layout(set = 0, binding = 2) uniform isamplerBuffer predecessor_texels;  // R32I: hull.predecessor
layout(std430, set = 0, binding = 3) writeonly buffer Triangles { int triangles[]; };
// host_device.h's COUNTER_TRIANGLES, _DEFERRED, _OVERFLOW, _IMPOSSIBLE
layout(std430, set = 0, binding = 4) buffer Counters { uint counters[]; };
// Row s (four ivec4): the star of s, counter-clockwise from index star_start, wrapping
// (star_common.glsl). Written only for sites that do not defer.
layout(std430, set = 0, binding = 5) buffer Star { ivec4 star4[]; };
// The same rows as words: until a site of a later phase walks, its row is its inbox: what the
// stars of earlier phases posted to it (the count in site_info_words, below).
layout(std430, set = 0, binding = 5) buffer StarWords { int star_words[]; };
// Site s: (star info (host_device.h), first output triangle of s or -1).
layout(std430, set = 0, binding = 6) buffer SiteInfo { ivec2 site_info[]; };
// The same words: word 2u + 1 of a site u of a later phase counts the posts of earlier phases
// to u's inbox, minus one (the host fills the words with -1 before the first phase; only finished
// stars post).
layout(std430, set = 0, binding = 6) buffer SiteInfoWords { int site_info_words[]; };
// Quantile cells' boundaries (unused with uniform cells).
layout(std430, set = 0, binding = 7) readonly buffer CellBounds { double cell_bounds[]; };

layout(push_constant) uniform Push { StarParams params; };

// Phases are ids modulo params.phase_count (a power of two).
int phase_of(int u) { return u & (params.phase_count - 1); }

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

// What the stars of earlier phases tell a site s, posted into its inbox (its row) by each
// finished star w of an earlier phase that has s in it (at most POSTS_MAX; the rest are dropped
// and searched for): w, and the neighbours of s just before and after w counter-clockwise
// around s (-1 where w's star does not tell: w met the hull). So a walk step s->v has a known
// apex where v is posted (the one after v) or where some posted w comes just after v (w itself).
const int POSTS_MAX = 5;  // triples in a 16-word row
struct Inbox {
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
int known_apex(Inbox e, int v, bool counter_clockwise) {
  if (v < 0) return -1;
  int from_v = counter_clockwise ? pick_where(e.w0, e.w1, e.after0, e.after1, v)
                                 : pick_where(e.w0, e.w1, e.before0, e.before1, v);
  int next = counter_clockwise ? pick_where(e.before0, e.before1, e.w0, e.w1, v)
                               : pick_where(e.after0, e.after1, e.w0, e.w1, v);
  return from_v >= 0 ? from_v : next;
}

// Where a walk is (not to be confused with a phase, the group of sites a dispatch walks).
const int WALK_NEAREST = 0;  // nearest_site v0 of s
const int WALK_CCW = 1;      // triangles (s, v, apex(s->v)) counter-clockwise from v0
const int WALK_CW = 2;       // the walk met the hull: (v, s, apex(v->s)) clockwise from v0
const int WALK_DONE = 3;
const int WALK_DEFER = 4;

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
void circle_region(dvec2 a, dvec2 b, dvec2 c, out ivec2 lo_cell, out ivec2 hi_cell) {
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

// ---- walk_star: one site's walk around its star ----------------------------------------------
// The walk's state, shared by its steps below (module-scope, so that each step is a function of
// no arguments; the compilers inline every step into main and keep the state in registers).
int s;              // the site
dvec2 ps;           // its point
int pred_s;         // its hull predecessor, or -1
int budget;         // loop iterations left before the site defers
int walk;           // WALK_*
bool impossible;    // a search found no candidate anywhere: cannot happen for a valid hull
bool handed_on;     // the first_pass met a candidate only the exact path decides
// The edge searched, a->b (for nearest_site: a = b = s).
int ia, ib;
dvec2 pa, pb;
// The edge in its own frame (B = b - a, |B|^2), for the apex filters.
dvec2 edge;
double edge2;
// Best candidate so far.
int best;
dvec2 best_p;
double best_d2;
// Boxes: visited (done), target (being scanned: target minus visited, row segment by row
// segment; segment `part` 0 is left of the visited box or the whole row, 1 right of it).
ivec2 vlo, vhi, tlo, thi;
int y, part, slot, slot_end;
int pending;        // the candidate left to decide_exactly, or -1
bool big_scan;      // the target box is large: a better candidate plans again (restart)
bool restart;
bool known;         // best came from the inbox: the search has nothing to scan
Inbox inbox;
// The star, in registers: counter-clockwise from index 0 up; clockwise (if the walk meets the
// hull) from index 15 down, so that the row read from index 16 - m on, wrapping, is the whole
// star counter-clockwise.
StarRow row;
int v0, v, deg, m;
bool closed;

// The site this invocation walks: phase params.phase's (ids modulo params.phase_count).
int site_of_invocation() { return (params.first_site + int(gl_GlobalInvocationID.x)) * params.phase_count + params.phase; }

// With EDGE_PART: whether s is among the sites this dispatch walks (of, or off, the grid's
// outer ring of cells).
bool in_edge_part(int site) {
  const ivec2 c = cell_of(site_at(site));
  const bool ring = min(min(c.x, c.y), min(params.cells - 1 - c.x, params.cells - 1 - c.y)) < 1;
  return ring == (EDGE_PART == 1);
}

// The walk's start: nearest_site's first box around s, an empty star.
void start_walk(int site) {
  s = site;
  budget = LOOP_BUDGET;
  ps = site_at(s);
  pred_s = predecessor_of(s);
  walk = WALK_NEAREST;
  impossible = false;
  handed_on = false;
  ia = s;
  ib = s;
  pa = ps;
  pb = ps;
  edge = dvec2(0.0lf);
  edge2 = 0.0lf;
  best = -1;
  best_p = ps;
  best_d2 = 0.0lf;
  vlo = ivec2(NONE_BELOW);
  vhi = ivec2(-NONE_BELOW);
  if (QUANTILE_CELLS) {  // cells of any width: the first box is the site's cell
    tlo = cell_of(ps);
    thi = tlo;
  } else {
    dvec2 nn_reach = NN_REACH / params.inv_width;  // inv_width > 0: the sites are not collinear
    tlo = cell_of(ps - nn_reach);
    thi = cell_of(ps + nn_reach);
  }
  y = tlo.y - 1;
  part = 1;
  slot = 0;
  slot_end = 0;
  pending = -1;
  big_scan = false;
  restart = false;
  inbox = Inbox(ivec4(-1), ivec4(-1), ivec4(-1), ivec4(-1), ivec4(-1), ivec4(-1));
  known = false;
  row = StarRow(ivec4(-1), ivec4(-1), ivec4(-1), ivec4(-1));
  v0 = -1;
  v = -1;
  deg = 0;
  m = 0;
  closed = false;
}

// The posts of earlier phases from s's inbox; the walk starts at the first of them (no
// nearest_site search).
void read_inbox() {
  int posted = min(site_info_words[2 * s + 1] + 1, POSTS_MAX);
  StarRow posts = StarRow(star4[4 * s], star4[4 * s + 1], star4[4 * s + 2], star4[4 * s + 3]);
  for (int k = 0; k < posted; ++k) {
    --budget;
    int before = row_pick(posts, 3 * k), w = row_pick(posts, 3 * k + 1), after = row_pick(posts, 3 * k + 2);
    bvec4 at0 = equal(ivec4(k), ivec4(0, 1, 2, 3)), at1 = equal(ivec4(k), ivec4(4, 5, 6, 7));
    inbox.w0 = mix(inbox.w0, ivec4(w), at0);
    inbox.w1 = mix(inbox.w1, ivec4(w), at1);
    inbox.before0 = mix(inbox.before0, ivec4(before), at0);
    inbox.before1 = mix(inbox.before1, ivec4(before), at1);
    inbox.after0 = mix(inbox.after0, ivec4(after), at0);
    inbox.after1 = mix(inbox.after1, ivec4(after), at1);
  }
  int first = max(max(max(inbox.w0.x, inbox.w0.y), max(inbox.w0.z, inbox.w0.w)),
                  max(max(inbox.w1.x, inbox.w1.y), max(inbox.w1.z, inbox.w1.w)));
  if (first >= 0) {  // the walk starts at a posted neighbour
    best = first;
    best_p = site_at(first);
    known = true;
    y = thi.y;  // an empty scan
  }
}

// The candidate loop over [slot, slot_end): straight-line, one exit. Stops at a candidate the
// filters leave to decide_exactly (pending), or at a better candidate when a large box was
// planned from a worse candidate's region (restart).
void scan_row_segment() {
  for (; slot < slot_end; ++slot) {
    if (--budget < 0) break;
    int ip = slot;  // sites are stored sorted by cell
    dvec2 p = site_at(ip);
    dvec3 q = apex_point(pa, p);  // in the nearest_site search a = s: q.z = |p - s|^2
    // The best's lift is formed again for each candidate: kept in the loop instead, its six
    // doubles cost lavapipe more than the operations (1M uniform: star shader 722-735 ms
    // formed again, 769-777 kept, 795-800 with the full filters; H100: 91 ms kept).
    int o = APEX_FILTERS ? apex_orient_filter(apex_lift(edge, edge2, q)) : orient2d_filter(pa, pb, p);
    int ic = APEX_FILTERS ? apex_incircle_filter(apex_lift(edge, edge2, apex_point_with(pa, best_p, best_d2)), q)
                          : incircle_filter(pa, pb, best_p, p);
    double d2 = q.z;
    // 0: reject, 1: better than the best, 2 (uncertain): the filters cannot tell. A restart may
    // visit best again; a, b (or s) are never candidates.
    int verdict = walk == WALK_NEAREST
                      ? ((best < 0 || d2 < best_d2 * (1.0lf - 1.0e-12lf)) ? 1
                         : (d2 > best_d2 * (1.0lf + 1.0e-12lf) ? 0 : 2))
                      : (o == -1 ? 0 : (o == uncertain ? 2 : (best < 0 ? 1 : (ic == -1 ? 0 : ic))));
    if (EXACT_LATTICE) {
      ApexLift lift = apex_lift(edge, edge2, q);  // lift.k: orient2d(a, b, p), exact
      double value = apex_incircle_value(apex_lift(edge, edge2, apex_point(pa, best_p)), q);
      int tie = value == 0.0lf && lift.k > 0.0lf && best >= 0 ? cocircular_perturbed_lattice(pa, pb, best_p, p) : 0;
      verdict = walk == WALK_NEAREST
                    ? ((best < 0 || d2 < best_d2 || (d2 == best_d2 && ip < best)) ? 1 : 0)
                    : (lift.k <= 0.0lf ? 0
                       : best < 0      ? 1
                       : value > 0.0lf ? 1
                       : value < 0.0lf ? 0
                       : tie == uncertain ? 2 : (tie > 0 ? 1 : 0));
    }
    if (ip == ia || ip == ib || ip == best) verdict = 0;
    bool better = verdict == 1;
    best = better ? ip : best;
    best_p = better ? p : best_p;
    best_d2 = better ? d2 : best_d2;
    if (verdict == 2 || (better && big_scan)) {
      pending = verdict == 2 ? ip : -1;
      restart = better;
      break;
    }
  }
}

// The scan loop: the target box minus the visited one, row segment by row segment, until it is
// done, the budget is spent, a candidate is pending or a restart is due.
void scan_box() {
  for (;;) {
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
    scan_row_segment();
    if (budget < 0 || pending >= 0 || restart) break;
  }
}

// No candidate in the boxes visited: twice as large a box around them.
void grow_box() {
  ivec2 grow = max(vhi - vlo + 1, ivec2(1));
  tlo = max(vlo - grow, ivec2(0));
  thi = min(vhi + grow, ivec2(params.cells - 1));
}

// The region the best candidate leaves (nearest_site: its distance; apex_search:
// circle_region): true when it lies in the cells visited (the search is over); the next box
// goes towards it.
bool aim_at_region() {
  ivec2 rlo, rhi;
  if (walk == WALK_NEAREST) {
    double reach = sqrt(best_d2) * (1.0lf + 1.0e-6lf) + ABS_MARGIN;
    rlo = cell_of(ps - dvec2(reach));
    rhi = cell_of(ps + dvec2(reach));
  } else {
    circle_region(pa, pb, best_p, rlo, rhi);
  }
  bool found = box_inside(rlo, rhi, vlo, vhi);
  // Towards the region, but by at most half the visited box per side: nearer candidates come
  // first and shrink the region (a far region is often a poor early candidate's).
  if (vlo.x > vhi.x) {
    // Restarted in a search's first box: the region within that box.
    tlo = max(rlo, tlo);
    thi = min(rhi, thi);
  } else {
    ivec2 reach = max((vhi - vlo + 1) >> 1, ivec2(1));
    tlo = max(min(vlo, rlo), vlo - reach);
    thi = min(max(vhi, rhi), vhi + reach);
  }
  return found;
}

// The search is over and c (best) is the answer: the walk's next step, and the steps after it
// that neighbours of earlier phases have taken already (their posts tell them: known_apex).
void take_steps(int c) {
  for (;;) {
    if (walk == WALK_NEAREST) {
      v0 = c;
      row_put(row, 0, c);
      deg = 1;
      v = c;
      walk = WALK_CCW;
    } else if (walk == WALK_CCW) {
      if (c == v0) {
        closed = true;
        walk = WALK_DONE;
      } else if (deg >= STAR_CAPACITY) {
        walk = WALK_DEFER;
      } else {
        row_put(row, deg, c);
        ++deg;
        v = c;
      }
    } else {
      if (c == v0 || deg + m >= STAR_CAPACITY) {
        walk = WALK_DEFER;
      } else {
        row_put(row, STAR_ROW - 1 - m, c);
        ++m;
        v = c;
      }
    }
    if (walk == WALK_CCW && pred_s == v) {
      walk = WALK_CW;  // s->v is an outer edge: the rest lies clockwise from v0
      v = v0;
    }
    if (walk == WALK_CW && predecessor_of(v) == s) walk = WALK_DONE;
    if (walk >= WALK_DONE || --budget < 0) break;
    c = known_apex(inbox, v, walk == WALK_CCW);
    if (c < 0) break;
  }
}

// apex_search of the walk's next edge: s->v counter-clockwise, v->s clockwise.
void start_apex_search() {
  dvec2 pv = site_at(v);
  ia = walk == WALK_CCW ? s : v;
  ib = walk == WALK_CCW ? v : s;
  pa = walk == WALK_CCW ? ps : pv;
  pb = walk == WALK_CCW ? pv : ps;
  precise dvec2 e = pb - pa;
  precise double e2 = e.x * e.x + e.y * e.y;
  edge = e;
  edge2 = e2;
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

// The pending candidate decided exactly; false when even the exact path cannot (uncertain).
// The scan resumes after it.
bool decide_exactly() {
  int ip = pending;
  dvec2 p = site_at(ip);
  int verdict = 0;
  if (walk == WALK_NEAREST) {
    bool ok = true;
    double e_new = squared_distance_certified(p, ps, ok);
    double e_old = squared_distance_certified(best_p, ps, ok);
    verdict = !ok ? 2 : (e_new < e_old ? 1 : 0);
    if (!ok && EXACT_DIFFERENCES) {
      int cmp = compare_distance_exact_differences(ps, p, best_p);
      verdict = cmp == uncertain ? 2 : (cmp < 0 ? 1 : 0);
    }
  } else {
    int o = orient2d_device(pa, pb, p);
    if (o == uncertain && EXACT_DIFFERENCES) o = orient2d_exact_differences(pa, pb, p);
    if (o == uncertain) {
      verdict = 2;
    } else if (o > 0) {
      int sign = best < 0                ? 1
                 : EXACT_DIFFERENCES ? incircle_perturbed_exact_differences(pa, pb, best_p, p)
                                     : incircle_perturbed_device(pa, pb, best_p, p);
      verdict = sign == uncertain ? 2 : (sign > 0 ? 1 : 0);
    }
  }
  if (verdict == 2) return false;
  if (verdict == 1) {
    dvec3 q = apex_point(pa, p);
    best = ip;
    best_p = p;
    best_d2 = q.z;
  }
  slot = ip + 1;
  pending = -1;
  return true;
}

// The walk, nested by how often each loop's body runs (see the top of this file): the exact
// loop around the search loop around scan_box. Ends with walk WALK_DONE or WALK_DEFER.
void walk_star() {
  for (;;) {    // exact loop
    for (;;) {  // search loop
      scan_box();
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
        if (vlo == ivec2(0) && vhi == ivec2(params.cells - 1)) {
          impossible = true;  // no candidate anywhere: cannot happen for a valid hull
          walk = WALK_DEFER;
          break;
        }
        grow_box();
      } else {
        found = aim_at_region();
      }
      y = tlo.y - 1;
      part = 1;
      slot = 0;
      slot_end = 0;
      big_scan = box_cells(tlo, thi) - box_cells(vlo, vhi) > params.big_scan_cells;
      if (!found) continue;

      take_steps(best);
      if (walk >= WALK_DONE || budget < 0) break;
      start_apex_search();
    }
    if (budget < 0) walk = WALK_DEFER;
    if (walk >= WALK_DONE) break;
    if (!EXACT_PATH) {
      handed_on = true;
      walk = WALK_DEFER;
      break;
    }
    if (!decide_exactly()) {
      walk = WALK_DEFER;
      break;
    }
  }
}

// Canary for lavapipe's loop cap: once it is reached every loop runs at most once, so a
// two-trip loop that trips once means some search above may have been cut short.
bool loop_cap_reached() {
  int canary = 0;
  for (int i = 0; i < min(params.site_count, 2); ++i) ++canary;
  return canary != 2;
}

// A site the walk leaves: handed on to the retry, or deferred to the seam stage.
void leave_site(bool cut) {
  if (handed_on && !cut) {
    site_info[s] = ivec2(int(STAR_HANDED_ON), -1);
    return;
  }
  if (impossible) atomicAdd(counters[COUNTER_IMPOSSIBLE], 1u);
  site_info[s] = ivec2(int(STAR_DEFERRED), -1);
  atomicAdd(counters[COUNTER_DEFERRED], 1u);
}

// Posts to the inbox of each neighbour u of a later phase: the triangles (s, star t-1, u) and
// (s, u, star t+1), i.e. around u, s comes just after star t+1 and just before star t-1.
void post_to_inboxes(uint info) {
  for (int t = 0; t < deg; ++t) {
    int u = star_at(row, info, t);
    if (phase_of(u) > params.phase) {  // u's count word starts at -1
      int k = atomicAdd(site_info_words[2 * u + 1], 1) + 1;
      if (k < POSTS_MAX) {
        star_words[16 * u + 3 * k] = t + 1 < deg || closed ? star_at(row, info, t + 1) : -1;
        star_words[16 * u + 3 * k + 1] = s;
        star_words[16 * u + 3 * k + 2] = t > 0 || closed ? star_at(row, info, t - 1) : -1;
      }
    }
  }
}

// The finished star: stored, its owned triangles counted, posted and emitted.
void finish_star() {
  deg += m;
  uint info = star_info(deg, m > 0 ? STAR_ROW - m : 0, closed);
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
    at = int(atomicAdd(counters[COUNTER_TRIANGLES], uint(count)));
    if (at + count > params.triangle_capacity) {
      atomicAdd(counters[COUNTER_OVERFLOW], 1u);
      at = -1;
    }
  }
  site_info[s] = ivec2(int(info), at);
  if (params.phase < params.phase_count - 1) post_to_inboxes(info);
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

void main() {
  int site = site_of_invocation();
  if (site >= params.site_count) return;
  if (RETRY && !star_handed_on(uint(site_info[site].x))) return;
  if (EDGE_PART != 0 && !in_edge_part(site)) return;
  start_walk(site);
  if (params.phase > 0) read_inbox();
  walk_star();
  bool cut = loop_cap_reached();
  if (walk == WALK_DEFER || cut) {
    leave_site(cut);
    return;
  }
  finish_star();
}
