// The device apex search and nearest-neighbour search over a uniform cell grid.
//
// The including kernel defines, before including this file:
//   dvec2 site_at(int id);              coordinates of a site
//   int cell_begin(int cell);           cell_start[] of the grid, offset by the grid's cell_base
//   int slot_site(int slot);            site id stored in a slot (identity or block-local list)
//
// Cells are indexed as in cells.glsl, the same rule as the host's bucketing.
#ifndef EXPANSE_GRID_GLSL
#define EXPANSE_GRID_GLSL

#include "cells.glsl"
#include "predicates.glsl"

// Mesa's llvmpipe (lavapipe) caps the loop iterations of one shader invocation (65535 back
// edges, shared by the SIMD lanes executing together) and then silently *breaks out of every
// loop*, which would make a search miss sites. So every search spends from this per-invocation
// budget and defers once it runs out; the backend sets the budget low on CPU devices only.
int loop_budget = 1000000000;

struct Grid {
  dvec2 origin;
  dvec2 inv_width;
  int cells;        // G: cells per side of the global grid
  ivec2 lo, hi;     // the cell range this grid holds (inclusive)
  int cell_base;    // offset of this grid in cell_start[]
};

const int SEARCH_FOUND = 0;
const int SEARCH_DEFER = 1;    // a predicate could not be decided on the device
const int SEARCH_NONE = 2;     // no candidate in the grid
const int SEARCH_OUTSIDE = 3;  // found, but the empty-circle region leaves the grid's cells

ivec2 cell_of(Grid g, dvec2 p) {
  return ivec2(cell_coord(p.x, g.origin.x, g.inv_width.x, g.cells),
               cell_coord(p.y, g.origin.y, g.inv_width.y, g.cells));
}

int local_cell(Grid g, int i, int j) { return (i - g.lo.x) + (j - g.lo.y) * (g.hi.x - g.lo.x + 1); }

// Cell range (xlo, ylo, xhi, yhi) covering circle(a, b, c) ∩ left half-plane of a->b, and the
// circle (centre, radius + margin) for a cheap "clearly outside" test. False when the circle is
// too ill-conditioned to bound in floating point; the caller then searches everything.
//
// Why the margin holds: we only accept triangles whose angle at a has sin >= 1e-4 (cross >=
// 1e-4 |ba| |ca|). Then the denominator 2 cross has relative error <= 3 eps / 1e-4, and the
// numerators' absolute errors are <= 5 eps (|ba| + |ca|) |ba| |ca|, so the computed centre is off
// by < 1e-11 (|ba| + |ca| + R); input rounding of ba, ca (relative eps) moves it by the same
// order. The margin 1e-6 (R + |ba| + |ca|) exceeds that by five orders of magnitude, and also
// covers sqrt/division that are not correctly rounded on some devices.
bool circle_region(Grid g, dvec2 a, dvec2 b, dvec2 c, out ivec4 range, out dvec3 circle) {
  precise dvec2 ba = b - a;
  precise dvec2 ca = c - a;
  precise double cross = ba.x * ca.y - ba.y * ca.x;
  double lb = length(ba), lc = length(ca);
  range = ivec4(0, 0, g.cells - 1, g.cells - 1);
  circle = dvec3(0.0lf, 0.0lf, -1.0lf);
  if (!(cross >= 1.0e-4lf * lb * lc)) {
    // Too flat to locate the centre. If c sees a-b at an obtuse angle, the region is the minor
    // segment, and every point x in it sees a-b at an angle >= angle(a c b) > 90 degrees: it lies
    // in the disc with diameter a-b (Thales), which needs no centre. Hull-hugging flat triangles
    // of uniform inputs are exactly this case; without it their searches scan the whole grid.
    precise dvec2 ac = a - c;
    precise dvec2 bc = b - c;
    double dot_c = ac.x * bc.x + ac.y * bc.y;
    if (!(dot_c < -1.0e-6lf * length(ac) * length(bc))) return false;
    dvec2 mid = 0.5lf * (a + b);
    double radius_t = 0.5lf * lb * (1.0lf + 1.0e-6lf) + 1.0e-6lf * lb + ABS_MARGIN;
    ivec2 tlo = cell_of(g, mid - dvec2(radius_t)), thi = cell_of(g, mid + dvec2(radius_t));
    range = ivec4(tlo, thi);
    circle = dvec3(mid, radius_t);
    return true;
  }
  precise double b2 = ba.x * ba.x + ba.y * ba.y;
  precise double c2 = ca.x * ca.x + ca.y * ca.y;
  precise double d = 2.0lf * cross;
  precise double ux = (ca.y * b2 - ba.y * c2) / d;
  precise double uy = (ba.x * c2 - ca.x * b2) / d;
  dvec2 centre = a + dvec2(ux, uy);
  double radius = sqrt(ux * ux + uy * uy);
  // Relative margin for the centre's error, plus an absolute one: sites are scaled below 1 in
  // magnitude, so a computed centre or extreme point is rounded by up to half an ulp of 1,
  // which is the whole scale of the geometry for inputs like 1e8 + 1e-6 * u.
  double margin = 1.0e-6lf * (radius + lb + lc) + ABS_MARGIN;
  dvec2 lo = min(a, b), hi = max(a, b);
  // Extreme points of the circle count only if they can be on the left of a->b.
  double tol = 2.0lf * margin * lb;
  dvec2 e[4] = dvec2[4](centre + dvec2(radius, 0.0lf), centre - dvec2(radius, 0.0lf),
                        centre + dvec2(0.0lf, radius), centre - dvec2(0.0lf, radius));
  for (int k = 0; k < 4; ++k) {
    dvec2 ea = e[k] - a;
    if (ba.x * ea.y - ba.y * ea.x >= -tol) {
      lo = min(lo, e[k]);
      hi = max(hi, e[k]);
    }
  }
  lo -= dvec2(margin);
  hi += dvec2(margin);
  ivec2 clo = cell_of(g, lo), chi = cell_of(g, hi);
  range = ivec4(clo, chi);
  circle = dvec3(centre, radius + margin);
  return true;
}

bool clearly_outside(dvec3 circle, dvec2 p) {
  if (circle.z < 0.0lf) return false;
  dvec2 d = p - circle.xy;
  return d.x * d.x + d.y * d.y > circle.z * circle.z;
}

// Visits the cells of ring r around m (Chebyshev distance r), clipped to [clip.xy, clip.zw].
// Calls VISIT(cell_i, cell_j) for each; written as a macro so the body can return/continue.
#define FOR_RING_CELLS(m, r, clip, BODY)                                              \
  {                                                                                   \
    int x0_ = max(m.x - r, clip.x), x1_ = min(m.x + r, clip.z);                       \
    int y0_ = max(m.y - r, clip.y), y1_ = min(m.y + r, clip.w);                       \
    for (int cj_ = y0_; cj_ <= y1_; ++cj_) {                                          \
      bool edge_row_ = (cj_ == m.y - r) || (cj_ == m.y + r);                          \
      int step_ = edge_row_ ? 1 : max(1, 2 * r);                                      \
      for (int ci_ = edge_row_ ? x0_ : m.x - r; ci_ <= x1_; ci_ += step_) {           \
        if (--loop_budget < 0) return SEARCH_DEFER;                                  \
        if (ci_ < x0_) continue;                                                      \
        int CI = ci_, CJ = cj_;                                                       \
        BODY                                                                          \
      }                                                                               \
    }                                                                                 \
  }

// apex(a->b) over the grid: the site c strictly left of a->b minimising the perturbed
// circle order. need_inside: report SEARCH_OUTSIDE when the final empty-circle region reaches
// cells the grid does not hold (a block's copy of the sites); otherwise the grid is everything.
int apex_search(Grid g, int ia, int ib, dvec2 a, dvec2 b, out int apex, out int apex_slot) {
  apex = -1;
  apex_slot = -1;
  ivec2 m = clamp(cell_of(g, 0.5lf * (a + b)), g.lo, g.hi);
  int max_r = max(max(m.x - g.lo.x, g.hi.x - m.x), max(m.y - g.lo.y, g.hi.y - m.y));
  dvec2 best_p = dvec2(0.0lf);
  bool bounded = false;
  ivec4 range = ivec4(g.lo, g.hi);
  dvec3 circle = dvec3(0.0lf, 0.0lf, -1.0lf);
  for (int r = 0; r <= max_r; ++r) {
    if (--loop_budget < 0) return SEARCH_DEFER;
    if (apex >= 0 && bounded) {
      // Visited so far: rings 0..r-1. Stop once they hold the region (within the grid).
      ivec4 need = ivec4(max(range.xy, g.lo), min(range.zw, g.hi));
      if (need.x >= m.x - (r - 1) && need.z <= m.x + (r - 1) && need.y >= m.y - (r - 1) &&
          need.w <= m.y + (r - 1))
        break;
    }
    ivec4 clip = ivec4(g.lo, g.hi);
    if (apex >= 0 && bounded) clip = ivec4(max(range.xy, g.lo), min(range.zw, g.hi));
    FOR_RING_CELLS(m, r, clip, {
      int cell = g.cell_base + local_cell(g, CI, CJ);
      int end = cell_begin(cell + 1);
      for (int slot = cell_begin(cell); slot < end; ++slot) {
        if (--loop_budget < 0) return SEARCH_DEFER;
        int ip = slot_site(slot);
        if (ip == ia || ip == ib) continue;
        dvec2 p = site_at(ip);
        if (apex >= 0 && clearly_outside(circle, p)) continue;
        int o = orient2d_device(a, b, p);
        if (o == uncertain) return SEARCH_DEFER;
        if (o <= 0) continue;
        if (apex >= 0) {
          int s = incircle_perturbed_device(a, b, best_p, p);
          if (s == uncertain) return SEARCH_DEFER;
          if (s <= 0) continue;
        }
        apex = ip;
        apex_slot = slot;
        best_p = p;
        bounded = circle_region(g, a, b, p, range, circle);
      }
    })
  }
  if (apex < 0) return SEARCH_NONE;
  if (!bounded) {
    // Unbounded region: the whole grid was searched; it is all there is only if the grid is
    // the whole domain.
    if (g.lo != ivec2(0) || g.hi != ivec2(g.cells - 1)) return SEARCH_OUTSIDE;
  } else if (range.x < g.lo.x || range.y < g.lo.y || range.z > g.hi.x || range.w > g.hi.y) {
    return SEARCH_OUTSIDE;
  }
  return SEARCH_FOUND;
}

// Nearest other site of s by an exact comparison of squared distances (exactly equal distances
// may resolve either way: any exact nearest neighbour is a Delaunay neighbour).
// SEARCH_OUTSIDE when the disc reaches cells the grid does not hold.
int nearest_site(Grid g, int is, out int nearest, out int nearest_slot) {
  nearest = -1;
  nearest_slot = -1;
  dvec2 s = site_at(is);
  ivec2 m = clamp(cell_of(g, s), g.lo, g.hi);
  int max_r = max(max(m.x - g.lo.x, g.hi.x - m.x), max(m.y - g.lo.y, g.hi.y - m.y));
  double best_d2 = 0.0lf;
  dvec2 best_p = s;
  ivec4 range = ivec4(g.lo, g.hi);
  for (int r = 0; r <= max_r; ++r) {
    if (--loop_budget < 0) return SEARCH_DEFER;
    if (nearest >= 0) {
      ivec4 need = ivec4(max(range.xy, g.lo), min(range.zw, g.hi));
      if (need.x >= m.x - (r - 1) && need.z <= m.x + (r - 1) && need.y >= m.y - (r - 1) &&
          need.w <= m.y + (r - 1))
        break;
    }
    ivec4 clip = ivec4(g.lo, g.hi);
    if (nearest >= 0) clip = ivec4(max(range.xy, g.lo), min(range.zw, g.hi));
    FOR_RING_CELLS(m, r, clip, {
      int cell = g.cell_base + local_cell(g, CI, CJ);
      int end = cell_begin(cell + 1);
      for (int slot = cell_begin(cell); slot < end; ++slot) {
        if (--loop_budget < 0) return SEARCH_DEFER;
        int ip = slot_site(slot);
        if (ip == is) continue;
        dvec2 p = site_at(ip);
        precise dvec2 d = p - s;
        precise double d2 = d.x * d.x + d.y * d.y;
        if (nearest >= 0) {
          if (d2 > best_d2 * (1.0lf + 1.0e-12lf)) continue;
          if (d2 >= best_d2 * (1.0lf - 1.0e-12lf)) {
            // Too close to call in floating point: compare exactly or give up.
            bool ok = true;
            double e_new = squared_distance_certified(p, s, ok);
            double e_old = squared_distance_certified(best_p, s, ok);
            if (!ok) return SEARCH_DEFER;
            if (!(e_new < e_old)) continue;
          }
        }
        nearest = ip;
        nearest_slot = slot;
        best_p = p;
        best_d2 = d2;
        double reach = sqrt(d2) * (1.0lf + 1.0e-6lf) + ABS_MARGIN;
        range = ivec4(cell_of(g, s - dvec2(reach)), cell_of(g, s + dvec2(reach)));
      }
    })
  }
  if (nearest < 0) return SEARCH_NONE;
  if (range.x < g.lo.x || range.y < g.lo.y || range.z > g.hi.x || range.w > g.hi.y)
    return SEARCH_OUTSIDE;
  return SEARCH_FOUND;
}

#endif
