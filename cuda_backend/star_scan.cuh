#pragma once
// One site's star found by box scans: the same walk as walk_star (star_walk.cuh), the searches
// shaped like the Vulkan kernel's (shaders/star.comp) so that a warp's threads stay together.
//
// walk_star nests each search in rings of cells, and each thread of a warp sits at a different
// depth of that nest (a ring, a cell, a candidate, an exact predicate): the warp runs each level
// for the threads that happen to be there and waits for the slowest. Here every thread runs one
// flat loop whose innermost body is the same for all of them, whatever the thread is searching:
//   candidate loop (innermost): one candidate site, floating-point filters only, no branches
//                               that differ by search phase;
//   scan loop:   the next row segment of the box being scanned. Cells are sorted row-major,
//                so a row of a box is one contiguous range of sites;
//   search loop: a box is scanned: plan the next box from the best candidate's region
//                (circle ∩ left half-plane, circle_region), or take the walk's next step;
//   exact loop:  a candidate the filters could not decide: exact predicates and CGAL's
//                perturbation (rare), then back into the scan after it.
// A search ends when the best candidate's region lies inside the cells visited.
#include "predicates/apex_filter.hpp"
#include "star_walk.cuh"

namespace expanse::detail::cuda {

/// Searches by box scans that re-plan on a better candidate once a box has grown past this many
/// cells (star.comp's big_scan_cells at two sites per cell: ~48 sites' worth of cells).
inline constexpr int kBigScanCells = 24;

/// Searches along a strip of the grid's two outermost columns or rows (BoundaryStrips) shorter than
/// this many cells keep their box scans.
inline constexpr int kStripMinCells = 16;

/// An apex search whose first box (the guess) would span more cells than this starts with the
/// cells along its edge instead.
inline constexpr int kLongEdgeCells = 64;

/// A box of cells, bounds inclusive; empty when x0 > x1.
struct CellBox {
  int x0, y0, x1, y1;
};

EXPANSE_DEVICE_FORCE int box_cells(const CellBox& b) {
  return max(b.x1 - b.x0 + 1, 0) * max(b.y1 - b.y0 + 1, 0);
}

EXPANSE_DEVICE_FORCE bool box_inside(const CellBox& inner, const CellBox& outer) {
  return inner.x0 >= outer.x0 && inner.y0 >= outer.y0 && inner.x1 <= outer.x1 && inner.y1 <= outer.y1;
}

/// The cells that hold every site with lo <= x <= hi, lo_y <= y <= hi_y (cell_x, cell_y are
/// monotone, so no rounding can leave a site out).
EXPANSE_DEVICE_FORCE CellBox cells_of(const GridView& g, double x_lo, double y_lo, double x_hi, double y_hi) {
  return {g.cell_x(x_lo), g.cell_y(y_lo), g.cell_x(x_hi), g.cell_y(y_hi)};
}

/// Whether box b of quantile cells holds every site with x_lo <= x <= x_hi, y_lo <= y <= y_hi:
/// box_inside(cells_of(g, x_lo, y_lo, x_hi, y_hi), b) decided by b's four boundaries instead of
/// four look-ups. Column j holds exactly the x with xb[j] <= x < xb[j + 1] (cell_x(x) is the
/// largest j with j == 0 or xb[j] <= x, the boundaries ascending), so cell_x(x_lo) >= b.x0
/// exactly when b.x0 == 0 or xb[b.x0] <= x_lo, and cell_x(x_hi) <= b.x1 exactly when
/// b.x1 == gx - 1 or x_hi < xb[b.x1 + 1]; rows alike. A NaN bound gives false (the look-ups then
/// decide).
EXPANSE_DEVICE_FORCE bool quantile_box_holds(const GridView& g, const CellBox& b, double x_lo, double y_lo,
                                             double x_hi, double y_hi) {
  if (b.x0 > b.x1 || b.y0 > b.y1) return false;
  return (b.x0 == 0 || load_readonly(g.xb + b.x0) <= x_lo) && (b.x1 == g.gx - 1 || x_hi < load_readonly(g.xb + b.x1 + 1)) &&
         (b.y0 == 0 || load_readonly(g.yb + b.y0) <= y_lo) && (b.y1 == g.gy - 1 || y_hi < load_readonly(g.yb + b.y1 + 1));
}

/// What a search still has to look at: the left half-plane of a->b (apex searches) and, once a
/// candidate is known, a disc holding the region where a better one could lie. Both only
/// shrink during a search, so cells outside them never need a look, now or later.
struct SearchBounds {
  bool apex = false;  ///< an apex search (the half-plane applies); false: nearest neighbour
  bool disc = false;
  double2 a, b;
  double ox = 0.0, oy = 0.0, reach = 0.0;
};

/// Narrows the row segment [*x0, *x1] of row y to the cells that can hold a site inside
/// `bounds`, with margins far above the rounding of these few operations (pruning only: the
/// candidates are still tested exactly). Sites on wide flat hull sides, and any long edge, have
/// a search box much larger than the thin region inside it; rows cut to it cost a fraction.
EXPANSE_DEVICE_FORCE void clip_row(const GridView& g, int y, const SearchBounds& bounds, int* x0, int* x1) {
  double yl, yh;
  g.y_bounds(y, &yl, &yh);
  double lo = -HUGE_VAL, hi = HUGE_VAL;
  if (bounds.disc) {
    const double dy = fmax(fmax(yl - bounds.oy, bounds.oy - yh), 0.0);
    if (dy > bounds.reach * (1.0 + 1e-9)) {
      *x1 = *x0 - 1;
      return;
    }
    const double half = sqrt(fmax(bounds.reach * bounds.reach * (1.0 + 4e-9) - dy * dy, 0.0)) * (1.0 + 1e-9) +
                        1e-9 * bounds.reach + 1e-300;
    lo = bounds.ox - half - 1e-15 * fabs(bounds.ox);
    hi = bounds.ox + half + 1e-15 * fabs(bounds.ox);
  }
  if (bounds.apex) {
    // Left of a->b: ex (py - ay) > ey (px - ax). In the row's band of y, for ey > 0 that is
    // x < ax + ex (py - ay) / ey at its largest; for ey < 0, x > the smallest.
    const double2 a = bounds.a;
    const double ex = bounds.b.x - a.x, ey = bounds.b.y - a.y;
    if (ey != 0.0) {
      const double run = ex / ey;  // one division a row; the slop covers its rounding
      const double t1 = run * (yl - a.y), t2 = run * (yh - a.y);
      const double slop = 1e-9 * (fabs(a.x) + fabs(t1) + fabs(t2) + fabs(ex)) + 1e-300;
      if (ey > 0.0)
        hi = fmin(hi, a.x + fmax(t1, t2) + slop);
      else
        lo = fmax(lo, a.x + fmin(t1, t2) - slop);
    } else {
      const double slop = 1e-9 * fabs(a.y) + 1e-300;
      if ((ex > 0.0 && yh < a.y - slop) || (ex < 0.0 && yl > a.y + slop)) {
        *x1 = *x0 - 1;
        return;
      }
    }
  }
  if (lo > -HUGE_VAL) *x0 = max(*x0, g.cell_x(lo));
  if (hi < HUGE_VAL) *x1 = min(*x1, g.cell_x(hi));
}

/// The exact verdict on candidate ip, which the filters could not decide: 1 if it is better
/// than `best` (nearer to site s, or a smaller circle's apex of a->b under CGAL's perturbation),
/// 0 if not, 2 if the device cannot decide. Out of line: the exact arithmetic needs far more
/// registers than the scan, and inlined it would set the register count, and so the occupancy,
/// of the whole kernel for a path few candidates take. It takes site ids and loads their points
/// itself: across the call the caller's live registers are spilled at the kernel's cap, and ten
/// doubles of arguments were ten more.
EXPANSE_DEVICE_NOINLINE int decide_exactly(const double2* points, bool nearest, int s, int a, int b, int best, int ip) {
  const double2 p = load_site(points, ip);
  if (nearest) {  // a filter leaves a nearest-neighbour candidate undecided only against a best
    const int cmp = compare_distance(load_site(points, s), p, load_site(points, best));
    return cmp == ex::uncertain ? 2 : (cmp < 0 || (cmp == 0 && ip < best)) ? 1 : 0;
  }
  const double2 pa = load_site(points, a), pb = load_site(points, b);
  const int o = orient(pa, pb, p);
  if (o == ex::uncertain) return 2;
  if (o <= 0) return 0;
  const int sign = best < 0 ? 1 : incircle_perturbed(pa, pb, load_site(points, best), p);
  return sign == ex::uncertain ? 2 : sign > 0 ? 1 : 0;
}

/// Who walks one site's star: a thread alone, or the 32 threads of a warp together, each testing
/// one of 32 consecutive candidates (CUDA only). A warp's walk is the thread's walk, decision for
/// decision: the candidates are still taken in order, the first that the filters flag (a better
/// one, or one they cannot decide) is dealt with as the thread would, and the scan resumes right
/// after it against the new best. So both make the same star, count the same work and defer the
/// same sites; a warp just gets through long rows of cells 32 candidates at a time.
enum class Walker { thread, warp };

/// ExactLattice: the sites satisfy exact_lattice_arithmetic (predicates/exact_lattice.hpp), so
/// the filters' values are exact and every candidate is decided in the scan. A template
/// parameter, not a flag: tested at run time it cost the other inputs' kernel 60% (H100, 4096^2
/// uniform star kernel 62.6 -> 100.5 ms).
///
/// FirstPass: the light walk of the kernels' first pass, which leaves its hard sites to the
/// second (a full walk, by a warp, with the full budget):
///  - no exact path: at the first candidate the filters cannot decide, the walk stops, deferred
///    with `handed_on` set. Without the out-of-line call the kernel keeps more of its walk in
///    registers (a value live across a call lives in local memory, and the candidate loop
///    reloads it): star kernel -2% (uniform) to -12% (lattice), H100;
///  - no row clipping (clip_row): for the typical search the cut costs more than the cells it
///    saves, and its bounds cost registers; the searches that need it (long thin regions along
///    the hull) run past the first pass's budget and are walked again with it. Star kernel
///    -21% (uniform) to -26% (gaussian) with no clipping anywhere (H100).
///
/// ReadsInbox: the walk of an odd site in the second of two phases (StarInbox), which starts at
/// a neighbour from its inbox and takes steps from it. A template parameter for the registers:
/// the reading compiled into every walk cost the one-phase star kernels 6% (H100).
///
/// Strips: an apex search whose region lies in the grid's two outermost columns or rows and runs
/// along them at least kStripMinCells cells scans that side's strip (BoundaryStrips, g.strips)
/// instead of boxes, where the strip's prefix is the shorter: the strip's sites in order of the inward key,
/// up to the region's inner bound, which shrinks with every better candidate. These are the
/// hull-hugging sites of inputs with straight hull sides (a uniform square): a nearly collinear
/// run of sites along a side leaves circles whose region is a sliver along the whole side, and
/// the box scans visited every row of it. Counted on the CPU (4096^2 uniform, one full walk):
/// the sites over 2^10 units spend 24.4 M of their 26.0 M units in such searches, whose final
/// regions' strip prefixes hold 3.8 M sites. Only the walks of the grid's edge and the warps'
/// second pass take it, on grids of equal cells (star_kernels.cu): the sites of the phases'
/// kernels are interior ones, and their registers are the star kernels' limit. These walks also
/// start a long edge's search along the edge (kLongEdgeCells).
///
/// Cells: the grid's kind where the caller knows it. The kernels walk each kind in a copy of the
/// walk of its own (GridKind::uniform compiled without the quantile look-ups), chosen per walk by
/// a branch the whole kernel takes the same way: in one walk for both, the look-ups' code and
/// registers weighed on the uniform grid's walks too.
template <Walker By = Walker::thread, bool ExactLattice = false, bool FirstPass = false, bool ReadsInbox = false,
          bool Strips = false, GridKind Cells = GridKind::any>
EXPANSE_DEVICE StarWalk walk_star_boxes(const GridView& grid, const int* pred, int i, int* row, unsigned budget,
                                        const StarInbox& inbox = {}) {
  const GridView g = of_kind<Cells>(grid);
  // Whether this walk compiles the scans across (TailColumns): the kernels' guided_tails walks
  // alone, so that the others' code stays as it was (the host's walks take any grid).
#if defined(__CUDA_ARCH__)
  constexpr bool kAcross = Cells == GridKind::guided_tails;
  // Whether the apex searches' candidate loop keeps the best's lift and loads the next point
  // ahead (below): on uniform cells and guided quantile cells, not on those with TailColumns.
  constexpr bool kLoopAhead = Cells == GridKind::uniform || Cells == GridKind::guided;
#else
  constexpr bool kAcross = true;
  constexpr bool kLoopAhead = true;  // the same decisions either way
#endif
#if !defined(__CUDACC__)
  static_assert(By == Walker::thread, "a warp walks only on the device");
#endif
  // In a warp every thread holds the same walk state; one of them writes the star.
  bool writer = true;
#if defined(__CUDACC__)
  if constexpr (By == Walker::warp) writer = (threadIdx.x & 31) == 0;
#endif
  enum Phase : int { nearest, ccw, cw, done, deferred };
  constexpr int kNone = 1 << 29;
  constexpr double eps = ex::epsilon;
  StarWalk w;
  const double2 ps = load_site(g.points, i);
  const int pred_s = pred[i];
  const CellBox whole{0, 0, g.gx - 1, g.gy - 1};
  int phase = nearest;
  DeferReason reason = DeferReason::undecided;
  // The edge searched, a->b (the nearest-neighbour search has a = b = s): s->v counter-clockwise,
  // v->s clockwise, so its ends are always i and v (v = -1 in the nearest-neighbour search).
  double2 pa = ps, pb = ps;
  int best = -1;
  double2 best_p = ps;
  double best_d2 = 0.0;
  // visited: cells done; target: the box being scanned (target minus visited, a row segment at
  // a time: in row y, `part` 0 is left of the visited box or the whole row, 1 right of it).
  CellBox visited{kNone, kNone, -kNone, -kNone};
  // First box of the nearest-neighbour search: the site's cell (one look-up an axis) and, on the
  // uniform grid, its neighbours within half a cell (about 9 candidates on uniform inputs, as
  // star.comp counted).
  auto nearest_box = [&]() {
    if (g.xb) {
      if constexpr (ExactLattice) return cells_of(g, ps.x, ps.y, ps.x, ps.y);  // the lattice's shape
      const int cx = g.cell_x(ps.x), cy = g.cell_y(ps.y);
      return CellBox{cx, cy, cx, cy};
    }
    return cells_of(g, ps.x - 0.5 * g.cell_w, ps.y - 0.5 * g.cell_h, ps.x + 0.5 * g.cell_w, ps.y + 0.5 * g.cell_h);
  };
  // A site whose inbox names a neighbour starts its walk there: no nearest-neighbour search
  // (an empty first box, and the search over at once), and no look-ups for it. A lattice's walks
  // take a shape of their own (the box, then the inbox; a region for a given neighbour too, below;
  // region_of_best's shape for them), the code measured fastest for them: in the other walks'
  // shape the 4096^2 lattice's star stage took 15.85 ms against 15.70 (H100).
  bool given = false;
  CellBox target{0, 0, -1, -1};
  if constexpr (ExactLattice) target = nearest_box();
  if constexpr (ReadsInbox) {
    if (const int start = inbox.first_neighbour(i); start >= 0) {
      best = start;
      given = true;
      target = CellBox{0, 0, -1, -1};
    }
  }
  if constexpr (!ExactLattice) {
    if (!given) target = nearest_box();
  }
  // The target is scanned a line at a time: a row, or a column of TailColumns (`across`) where
  // the box lies in one side's copied columns and is taller than wide. `y` is the line.
  bool across = false;
  int y = target.y0 - 1, part = 1;
  std::uint32_t slot = 0, slot_end = 0;
  int pending = -1;
  bool big_scan = false, narrow = false;
  int v0 = -1, v = -1;
  unsigned work = 0, predicates = 0;
  SearchBounds bounds;
  // Strips: the side whose strip is being scanned (-1: boxes), and the last region's bounds.
  int strip = -1;
  CircleRegion last_region{};

  // The cells where a site better than `best` could lie, with `bounds` set to match. With
  // `inside` (a box of quantile cells, the one just scanned), in the second phase's walks
  // (ReadsInbox), that box itself where it holds the region (quantile_box_holds): most searches
  // end there (kuzmin, counted on the CPU: 80% of these tests), and the region's four look-ups
  // are half of the light walk's. The first phase's walks are a little faster without it
  // (H100, 4096^2: kuzmin's first phase 32.15 ms against 32.35 with it). The look-up after the
  // branches rather than in each: ptxas places kuzmin's spills better so (52.95 -> 52.56 ms). A
  // lattice's walks take a shape of their own (see `given`).
  auto region_of_best = [&](const CellBox* inside = nullptr) {
    if constexpr (ExactLattice) {
      static_cast<void>(inside);
      CellBox region = whole;
      if (phase == nearest) {
        const double reach = sqrt(best_d2) * (1.0 + 1e-6) + 4.0 * eps * (fabs(ps.x) + fabs(ps.y)) + 1e-160;
        region = cells_of(g, ps.x - reach, ps.y - reach, ps.x + reach, ps.y + reach);
        bounds.disc = true;
        bounds.ox = ps.x;
        bounds.oy = ps.y;
        bounds.reach = reach;
      } else {
        CircleRegion r;
        if (circle_region(pa, pb, best_p, &r)) {
          if constexpr (Strips) last_region = r;
          region = cells_of(g, r.x_lo, r.y_lo, r.x_hi, r.y_hi);
          bounds.disc = true;
          bounds.ox = r.ox;
          bounds.oy = r.oy;
          bounds.reach = r.reach;
        }
      }
      return region;
    } else {
      double x_lo, y_lo, x_hi, y_hi;
      if (phase == nearest) {
        // Every site at least as near as the best lies within `reach` of s (rounding of d2, of
        // sqrt and of the box's corners, and underflow in d2, all covered).
        const double reach = sqrt(best_d2) * (1.0 + 1e-6) + 4.0 * eps * (fabs(ps.x) + fabs(ps.y)) + 1e-160;
        x_lo = ps.x - reach;
        y_lo = ps.y - reach;
        x_hi = ps.x + reach;
        y_hi = ps.y + reach;
        bounds.disc = true;
        bounds.ox = ps.x;
        bounds.oy = ps.y;
        bounds.reach = reach;
      } else {
        CircleRegion r;
        if (!circle_region(pa, pb, best_p, &r)) return whole;
        if constexpr (Strips) last_region = r;
        x_lo = r.x_lo;
        y_lo = r.y_lo;
        x_hi = r.x_hi;
        y_hi = r.y_hi;
        bounds.disc = true;
        bounds.ox = r.ox;
        bounds.oy = r.oy;
        bounds.reach = r.reach;
      }
      if (ReadsInbox && g.xb && inside && quantile_box_holds(g, *inside, x_lo, y_lo, x_hi, y_hi)) return *inside;
      return cells_of(g, x_lo, y_lo, x_hi, y_hi);
    }
  };

  // Strips: the side whose strip holds `region` (the last region_of_best's) and runs along it
  // far enough that its prefix up to the region's inner bound is the cheaper scan, with that
  // prefix's length in *end; else -1. Box scans cost a row a cell along the side plus its
  // sites (two on quantile cells, 3.5 on uniform ones), so a prefix under two sites a cell wins.
  auto strip_for = [&](const CellBox& region, std::uint32_t* end) {
    int side = -1, along = 0;
    if (region.x1 <= 1 || region.x0 >= g.gx - 2) {
      side = region.x1 <= 1 ? kStripLeft : kStripRight;
      along = region.y1 - region.y0 + 1;
    }
    if ((region.y1 <= 1 || region.y0 >= g.gy - 2) && region.x1 - region.x0 + 1 > along) {
      side = region.y1 <= 1 ? kStripBottom : kStripTop;
      along = region.x1 - region.x0 + 1;
    }
    if (side < 0 || along < kStripMinCells) return -1;
    const double inner = side == kStripLeft    ? last_region.x_hi
                         : side == kStripRight ? -last_region.x_lo
                         : side == kStripBottom ? last_region.y_hi
                                                : -last_region.y_lo;
    const int prefix = strip_prefix(g.strips, side, strip_key(inner));
    if (prefix >= 2 * along) return -1;
    *end = static_cast<std::uint32_t>(prefix);
    return side;
  };
  // The candidate at `slot`: a site id in box scans, the strip's k-th site in strip scans.
  auto site_at = [&](std::uint32_t k) {
    if constexpr (Strips) {
      if (strip >= 0) return load_readonly(g.strips.ids + static_cast<std::size_t>(strip) * g.strips.capacity + k);
    }
    return static_cast<int>(k);
  };
  // Whether the target's lines are TailColumns' columns, and whether the scan is across (a
  // strip's scan is not, whatever the box before it).
  auto in_columns = [&]() { return kAcross && g.tail.ids && across; };
  auto scanning_across = [&]() { return in_columns() && !(Strips && strip >= 0); };
  // The candidate at `slot` in any scan: TailColumns' k-th site in a scan across.
  auto slot_site = [&](std::uint32_t k) {
    if (scanning_across()) return load_readonly(g.tail.ids + k);
    return site_at(k);
  };
  // Whether line l of the target crosses the visited box (then it has two parts), and the
  // target's last line.
  auto crosses_visited = [&](int l) {
    return in_columns() ? l >= visited.x0 && l <= visited.x1 : l >= visited.y0 && l <= visited.y1;
  };
  auto last_line = [&]() { return in_columns() ? target.x1 : target.y1; };
  // Starts the scan of a new target: across where TailColumns holds it and it is taller than wide.
  // (`across` is never read without kAcross, so that other walks keep no trace of it.)
  auto begin_target = [&]() {
    if constexpr (kAcross) {
      const int w = g.tail.width;
      across = g.tail.ids && (target.x1 < w || target.x0 >= g.gx - w) &&
               target.y1 - target.y0 > target.x1 - target.x0;
      y = (across ? target.x0 : target.y0) - 1;
    } else {
      y = target.y0 - 1;
    }
  };

  // Row y's part (0: left of the visited box or the whole row; 1: right of it) of the target
  // box minus the visited one, cut to `bounds`: sites [*first, *last).
  auto segment_of = [&](int row_y, int row_part, std::uint32_t* first, std::uint32_t* last) {
    if (in_columns()) {
      // Column row_y of TailColumns, not cut to `bounds`: a box taller than wide in these wide
      // columns is a region narrower than a column, and the disc's chord in the column nearest
      // its centre is the region's whole height (cut, kuzmin 4096^2 counted on the CPU the same
      // work to the unit).
      const bool cols = row_y >= visited.x0 && row_y <= visited.x1;
      const int y0 = (cols && row_part == 1) ? visited.y1 + 1 : target.y0;
      const int y1 = (cols && row_part == 0) ? visited.y0 - 1 : target.y1;
      *first = *last = 0;
      if (y0 <= y1) {
        const int c0 = tail_column_index(row_y, g.gx, g.tail.width) * g.gy + y0;
        *first = load_cell_start(g.tail.start, c0);
        *last = load_cell_start(g.tail.start, c0 + (y1 - y0) + 1);
      }
      return;
    }
    const bool rows = row_y >= visited.y0 && row_y <= visited.y1;
    int x0 = (rows && row_part == 1) ? visited.x1 + 1 : target.x0;
    int x1 = (rows && row_part == 0) ? visited.x0 - 1 : target.x1;
    *first = *last = 0;
    if (!FirstPass && x0 <= x1 && (bounds.apex || bounds.disc)) clip_row(g, row_y, bounds, &x0, &x1);
    if (x0 <= x1) {
      const int c0 = row_y * g.gx + x0;
      *first = load_cell_start(g.cell_start, c0);
      *last = load_cell_start(g.cell_start, c0 + (x1 - x0) + 1);
    }
  };
  // Candidate ip's verdict against the best: 0 reject, 1 better than the best, 2 the
  // filters cannot tell. Straight-line: no branch that differs by search phase. Neither counts
  // the predicates nor turns away a, b and the best (`excluded`): the thread's candidate loop
  // does both where it can do them cheaper (judge does them for each candidate). `left`: the
  // orientation is certainly positive (never in the nearest-neighbour search, whose edge is a
  // point); an apex search's candidate costs two predicates where it is and a best exists,
  // else one. `best_lift`: the best's lift where the caller keeps it (else formed here);
  // `loaded`: p holds the candidate's point already.
  auto judge_raw = [&](const ex::ApexEdge& edge, int ip, double2& p, double& d2, bool& left,
                       const ex::ApexLift* best_lift = nullptr, bool loaded = false) {
    if (!loaded) p = load_site(g.points, ip);
    // The filters in the edge's frame (apex_filter.hpp). The edge and the best's lift are
    // formed here rather than kept as the walk's state: registers cost this kernel more than
    // the few operations (ptxas itself forms the edge's B and |B|^2 once a row segment). The
    // apex searches' own loop (below) passes its edge and keeps the lift as the loop's state
    // (`best_lift`), which fits. With little work independent of the candidate's point, ptxas
    // starts on the point straight after its load.
    const ex::ApexPoint q = ex::apex_point(edge, p.x, p.y);
    d2 = q.d2;  // in the nearest-neighbour search a = s: |p - s|^2
    const ex::FilterSigns o = ex::apex_orient_signs(ex::apex_lift(edge, q));
    // The best in the edge's frame: its |C|^2 is best_d2, kept in that frame (take, and the
    // exact path below), the same rounded value apex_point would form again.
    const ex::ApexPoint c{ex::sub(best_p.x, pa.x), ex::sub(best_p.y, pa.y), best_d2};
    const ex::FilterSigns ic = ex::apex_incircle_signs(best_lift ? *best_lift : ex::apex_lift(edge, c), q);
    // Squared distances carry a few ulps of relative error, and none that matters above
    // 2^-960.
    int verdict;
    if constexpr (ExactLattice) {
      // The values are exact (exact_lattice_arithmetic): decided here, as decide_exactly
      // would: equal distances by site id, cocircular candidates by CGAL's perturbation, its
      // orientations exact in plain doubles too (the exact fallback of orient(), inlined into
      // the scan, held the 4096^2 lattice at 121 ms against 34, H100).
      const double k = ex::apex_lift(edge, q).k;  // orient2d(a, b, p)
      if (phase == nearest) {
        verdict = best < 0 || d2 < best_d2 || (d2 == best_d2 && ip < best) ? 1 : 0;
      } else if (k <= 0.0) {
        verdict = 0;
      } else if (best < 0) {
        verdict = 1;
      } else {
        const double in = ex::apex_incircle_value(ex::apex_lift(edge, ex::apex_point(edge, best_p.x, best_p.y)), q);
        const int tie = in == 0.0 ? cocircular_perturbed_by(
                                        pa, pb, best_p, p,
                                        [](double2 x, double2 y, double2 z) { return orient_on_lattice(x, y, z); }) : 0;
        verdict = in > 0.0 ? 1 : in < 0.0 ? 0 : tie > 0 ? 1 : 0;
      }
      left = k > 0.0;
      return verdict;
    }
    if (phase == nearest) {
      verdict = best < 0 ? 1
                : best_d2 < 0x1p-960 ? 2
                : d2 < best_d2 * (1.0 - 1e-12) ? 1
                : d2 > best_d2 * (1.0 + 1e-12) ? 0 : 2;
    } else {
      // Right of a->b, or outside the best's circle: rejected. Left, and inside it (or no best
      // yet): better. Anything else the filters cannot tell.
      const bool reject = o.negative || (o.positive && best >= 0 && ic.negative);
      const bool better = o.positive && (best < 0 || ic.positive);
      verdict = reject ? 0 : better ? 1 : 2;
    }
    left = o.positive;
    return verdict;
  };
  // a, b and the best are never candidates. No filter rejects them (each is a zero
  // orientation, incircle or distance, or the best's own distance), so only a flagged
  // candidate needs the test.
  auto excluded = [&](int ip) { return ip == i || ip == v || ip == best; };
  auto judge = [&](int ip, double2& p, double& d2) {
    bool left;
    int verdict = judge_raw(ex::apex_edge(pa.x, pa.y, pb.x, pb.y), ip, p, d2, left);
    predicates += phase != nearest ? 1u + (left && best >= 0) : 0u;
    if (verdict != 0 && excluded(ip)) verdict = 0;
    return verdict;
  };
  // What the thread does with a flagged candidate: take it if better, and leave the
  // candidate loop to decide it exactly or, in a large box planned from a worse
  // candidate's region, to narrow the rest of the scan to the better one's.
  auto take = [&](int ip, int verdict, double2 p, double d2) {
    if (verdict == 1) {
      best = ip;
      best_p = p;
      best_d2 = d2;
    }
    if (verdict == 2 || (verdict == 1 && big_scan)) {
      pending = verdict == 2 ? ip : -1;
      narrow = verdict == 1;
      return true;
    }
    return false;
  };
#if defined(__CUDACC__)
  // The warp's lanes test one candidate each (a lane whose `valid` is false, none), in the
  // thread's order. `seen`: how many the thread would have tested, up to and including the first
  // flagged one (else `available`, at most 32); predicates are counted the same way. `first`: that
  // lane (-1: none flagged), with its verdict, point and squared distance broadcast to all lanes.
  struct LaneTest {
    unsigned seen;
    int first, verdict;
    double2 p;
    double d2;
  };
  auto test_lanes = [&](bool valid, std::uint32_t candidate, unsigned available) {
    double2 p = best_p;
    double d2 = 0.0;
    const unsigned saved = predicates;
    const int verdict = valid ? judge(static_cast<int>(candidate), p, d2) : 0;
    const unsigned flagged = __ballot_sync(0xffffffffu, verdict != 0);
    LaneTest t{flagged ? static_cast<unsigned>(__ffs(flagged)) : min(32u, available), -1, 0, p, d2};
    if ((threadIdx.x & 31) >= t.seen) predicates = saved;
    if (flagged) {
      t.first = static_cast<int>(t.seen) - 1;
      t.verdict = __shfl_sync(0xffffffffu, verdict, t.first);
      t.p = make_double2(__shfl_sync(0xffffffffu, p.x, t.first), __shfl_sync(0xffffffffu, p.y, t.first));
      t.d2 = __shfl_sync(0xffffffffu, d2, t.first);
    }
    return t;
  };
  // The warp's row fetch: lane k takes row y + 1 + k (up to 32 rows, not past the target box),
  // both its parts, and the lanes then test the rows' candidates 32 at a time in the thread's
  // order. The first flagged candidate leaves the walk where the thread would stand on meeting
  // it (its row, part and slot, the work counted so far) and is taken as the thread would; with
  // none, the walk stands after the last row.
  auto scan_rows_together = [&]() {
    const unsigned lane = threadIdx.x & 31;
    const int count = min(32, last_line() - y);
    const int row_y = y + 1 + static_cast<int>(lane);
    const bool mine = static_cast<int>(lane) < count;
    const bool rows = crosses_visited(row_y);
    std::uint32_t a0 = 0, a1 = 0, b0 = 0, b1 = 0;
    if (mine) {
      segment_of(row_y, 0, &a0, &a1);
      if (rows) segment_of(row_y, 1, &b0, &b1);
    }
    const unsigned steps = mine ? (rows ? 2u : 1u) : 0u;  // row setups, as the thread counts them
    const unsigned len_a = a1 - a0, len = len_a + (b1 - b0);
    unsigned ends = len, step_ends = steps;  // inclusive prefix sums over the lanes
    for (int d = 1; d < 32; d <<= 1) {
      const unsigned e = __shfl_up_sync(0xffffffffu, ends, d), t = __shfl_up_sync(0xffffffffu, step_ends, d);
      if (static_cast<int>(lane) >= d) {
        ends += e;
        step_ends += t;
      }
    }
    const unsigned total = __shfl_sync(0xffffffffu, ends, 31), total_steps = __shfl_sync(0xffffffffu, step_ends, 31);
    for (unsigned base = 0; base < total; base += 32) {
      const unsigned j = base + lane;
      // The lane whose rows hold candidate j: the first whose inclusive end exceeds j.
      int owner = 0;
      for (int stride = 16; stride >= 1; stride >>= 1) {
        const unsigned probe = __shfl_sync(0xffffffffu, ends, owner + stride - 1);
        if (probe <= j) owner += stride;
      }
      const unsigned owner_end = __shfl_sync(0xffffffffu, ends, owner);
      const unsigned owner_len = __shfl_sync(0xffffffffu, len, owner);
      const unsigned owner_len_a = __shfl_sync(0xffffffffu, len_a, owner);
      const std::uint32_t owner_a0 = __shfl_sync(0xffffffffu, a0, owner), owner_b0 = __shfl_sync(0xffffffffu, b0, owner);
      const unsigned k = j - (owner_end - owner_len);
      const std::uint32_t candidate_slot = k < owner_len_a ? owner_a0 + k : owner_b0 + (k - owner_len_a);
      std::uint32_t candidate = candidate_slot;
      if constexpr (kAcross)
        candidate = j < total ? static_cast<std::uint32_t>(slot_site(candidate_slot)) : candidate_slot;
      const LaneTest t = test_lanes(j < total, candidate, total - base);
      if (t.first < 0) continue;
      // The thread would stand at the flagged candidate's row and part, having set up every
      // segment before it and tested every candidate before it.
      const int first = t.first;
      const int at_owner = __shfl_sync(0xffffffffu, owner, first);
      const unsigned at_k = __shfl_sync(0xffffffffu, k, first);
      const unsigned owner_steps_before = __shfl_sync(0xffffffffu, step_ends - steps, at_owner);
      const unsigned at_len_a = __shfl_sync(0xffffffffu, len_a, at_owner);
      const int at_part = at_k < at_len_a ? 0 : 1;
      const std::uint32_t at_a1 = __shfl_sync(0xffffffffu, a1, at_owner), at_b1 = __shfl_sync(0xffffffffu, b1, at_owner);
      work += owner_steps_before + static_cast<unsigned>(at_part + 1) + base + t.seen;
      y = y + 1 + at_owner;
      part = at_part;
      const int ip = static_cast<int>(__shfl_sync(0xffffffffu, candidate, first));
      slot_end = at_part == 0 ? at_a1 : at_b1;
      if constexpr (kAcross)
        slot = __shfl_sync(0xffffffffu, candidate_slot, first);
      else
        slot = static_cast<std::uint32_t>(ip);
      if (!take(ip, t.verdict, t.p, t.d2)) ++slot;
      return;
    }
    // None flagged: after the last row, as the thread would leave it.
    work += total_steps + total;
    y += count;
    part = crosses_visited(y) ? 1 : 0;
    slot = slot_end = 0;
  };
#endif
  for (;;) {    // exact loop
    for (;;) {  // search loop
      for (;;) {  // scan loop
        bool batched = false;
#if defined(__CUDACC__)
        // A warp fetches the next rows' segments together (rows of a box are often a cell or
        // two wide, too few candidates for 32 lanes one segment at a time).
        if constexpr (By == Walker::warp) {
          if (strip < 0 && slot >= slot_end && !(part == 0 && crosses_visited(y)) && y < last_line()) {
            batched = true;
            scan_rows_together();
          }
        }
#endif
        if (!batched) {
          if (slot >= slot_end) {
            if (Strips && strip >= 0) break;  // the strip's prefix is scanned
            if (++work > budget) break;
            const bool in_rows = crosses_visited(y);  // before `part`, as the code before the scans across
            if (part == 0 && in_rows) {
              part = 1;
            } else {
              part = 0;
              ++y;
            }
            if (y > last_line()) break;
            segment_of(y, part, &slot, &slot_end);
          }
          if constexpr (By == Walker::thread) {
            // A warp's lanes leave this loop as their row segments end and wait there for the
            // longest (7.2 lanes of 32 test candidates on average; ncu, H100); the loop's state
            // stays in registers only so.
            //
            // One loop for each kind of search, each compiled for it (the phase is fixed within a
            // row segment): the apex searches' loop tests no phase and keeps no branch around the
            // nearest-neighbour verdict, and counts the predicates without a test of the best:
            // two for a candidate left of the edge, taken back where no best exists yet, and
            // then the candidate is flagged (it is better), so the correction waits for the flag.
            // a, b and the best are turned away only where the filters flag them. The apex loop
            // keeps the best's lift and loads the next point ahead (57 instructions a candidate;
            // 4096^2 uniform 29.2 ms GPU-only against 30.2 without, H100, 2026-11-28). Kuzmin's
            // cells (TailColumns) lost 0.4 ms with those two and keep the loop without them
            // (kLoopAhead; kuzmin 45.4 -> 44.3 ms).
            if (ExactLattice || phase == nearest) {
              // (A lattice keeps this loop: with the apex searches' loop below its 4096^2 stars
              // took 16.35 ms against 15.87, H100.)
              for (; slot < slot_end; ++slot) {  // candidate loop: straight-line, one exit
                ++work;
                double2 p;
                double d2;
                const int ip = slot_site(slot);
                const int verdict = judge(ip, p, d2);
                if (verdict != 0 && take(ip, verdict, p, d2)) break;
                if (work > budget) break;
              }
            } else {
              const ex::ApexEdge edge = ex::apex_edge(pa.x, pa.y, pb.x, pb.y);
              auto lift_of_best = [&]() {
                return ex::apex_lift(edge, ex::ApexPoint{ex::sub(best_p.x, pa.x), ex::sub(best_p.y, pa.y), best_d2});
              };
              // kLoopAhead: the best's lift kept, and the next candidate's point loaded while
              // this one is tested (the last one's again at the segment's end: no branch), since
              // little else is left to hide the load's latency.
              ex::ApexLift best_lift{};
              double2 next = ps;
              if constexpr (kLoopAhead) {
                best_lift = lift_of_best();
                if (slot < slot_end) next = load_site(g.points, slot_site(slot));
              }
              for (; slot < slot_end; ++slot) {  // candidate loop: straight-line, one exit
                ++work;
                double2 p = next;
                if constexpr (kLoopAhead) next = load_site(g.points, slot_site(min(slot + 1, slot_end - 1)));
                double d2;
                bool left;
                const int ip = slot_site(slot);
                const int verdict = judge_raw(edge, ip, p, d2, left, kLoopAhead ? &best_lift : nullptr, kLoopAhead);
                predicates += left ? 2u : 1u;
                if (verdict != 0) {
                  if (left && best < 0) --predicates;
                  if (!excluded(ip) && take(ip, verdict, p, d2)) break;
                  if constexpr (kLoopAhead) best_lift = lift_of_best();
                }
                if (work > budget) break;
              }
            }
          }
  #if defined(__CUDACC__)
          if constexpr (By == Walker::warp) {
            const unsigned lane = threadIdx.x & 31;
            while (slot < slot_end) {  // 32 candidates at a time, the first flagged one taken
              const std::uint32_t mine = slot + lane;
              const bool valid = mine < slot_end;
              const LaneTest t = test_lanes(valid, valid ? static_cast<std::uint32_t>(slot_site(mine)) : mine,
                                            slot_end - slot);
              work += t.seen;
              if (t.first < 0) {
                slot += t.seen;
                if (work > budget) break;
                continue;
              }
              slot += static_cast<std::uint32_t>(t.first);
              const int ip = slot_site(slot);
              if (take(ip, t.verdict, t.p, t.d2)) break;
              ++slot;
              if (work > budget) break;
            }
          }
  #endif
        }
        if (work > budget || pending >= 0) break;
        if (narrow) {
          // Cells outside both the visited box and the new region need no look, now or later
          // (regions only shrink). Rows already scanned were scanned wider: no harm.
          narrow = false;
          const CellBox region = region_of_best();
          if (Strips && strip >= 0) {
            // The strip's prefix shrinks to the better candidate's region.
            std::uint32_t end = slot_end;
            if (strip_for(region, &end) == strip) slot_end = min(slot_end, end);
            continue;
          }
          const CellBox keep = visited.x0 > visited.x1
                                   ? region
                                   : CellBox{min(visited.x0, region.x0), min(visited.y0, region.y0),
                                             max(visited.x1, region.x1), max(visited.y1, region.y1)};
          target = {max(target.x0, keep.x0), max(target.y0, keep.y0), min(target.x1, keep.x1),
                    min(target.y1, keep.y1)};
          big_scan = box_cells(target) - box_cells(visited) > kBigScanCells;
        }
      }
      if (work > budget || pending >= 0) break;

      // The target box is scanned, or the strip (whose prefix holds the whole region).
      bool found = false;
      if (Strips && strip >= 0) {
        strip = -1;
        found = true;
      } else {
        visited = target;
        if (best < 0) {
          if (box_inside(whole, visited)) {  // no candidate anywhere: not for a valid hull
            reason = DeferReason::no_apex;
            phase = deferred;
            break;
          }
          const int grow_x = max(visited.x1 - visited.x0 + 1, 1), grow_y = max(visited.y1 - visited.y0 + 1, 1);
          target = {max(visited.x0 - grow_x, 0), max(visited.y0 - grow_y, 0), min(visited.x1 + grow_x, whole.x1),
                    min(visited.y1 + grow_y, whole.y1)};
        } else {
          // (A site the inbox gave its nearest neighbour has found it: no region.)
          const CellBox region = given && !ExactLattice ? visited : region_of_best(&visited);
          found = given || box_inside(region, visited);
          given = false;
          if constexpr (Strips) {
            std::uint32_t end = 0;
            if (!found && phase != nearest && g.strips.ids && (strip = strip_for(region, &end)) >= 0) {
              slot = 0;
              slot_end = end;
              big_scan = true;  // a better candidate narrows the prefix (take, then `narrow`)
              continue;
            }
          }
          // Towards the region, by at most half the visited box per side: nearer candidates
          // come first and shrink the region (a far region is often a poor early candidate's).
          const int rx = max((visited.x1 - visited.x0 + 1) >> 1, 1), ry = max((visited.y1 - visited.y0 + 1) >> 1, 1);
          target = {max(min(visited.x0, region.x0), visited.x0 - rx), max(min(visited.y0, region.y0), visited.y0 - ry),
                    min(max(visited.x1, region.x1), visited.x1 + rx), min(max(visited.y1, region.y1), visited.y1 + ry)};
        }
      }
      begin_target();
      part = 1;
      slot = slot_end = 0;
      big_scan = box_cells(target) - box_cells(visited) > kBigScanCells;
      if (!found) continue;

      // The search is over: best is the answer. The walk's next step, as in walk_star, and
      // the steps after it that the inbox gives (StarInbox).
      for (int c = best;;) {
        if (phase == nearest) {
          v0 = c;
          if (writer) row[0] = c;
          w.ccw = 1;
          v = c;
          phase = ccw;
        } else if (c == v0) {
          if (phase == ccw) {
            w.closed = true;
            phase = done;
          } else {
            reason = DeferReason::no_apex;  // a clockwise walk cannot close the star
            phase = deferred;
          }
        } else if (w.ccw + w.cw >= kStar) {
          reason = DeferReason::full_row;
          phase = deferred;
        } else {
          if (writer) row[phase == ccw ? w.ccw : kStar - 1 - w.cw] = c;
          if (phase == ccw)
            ++w.ccw;
          else
            ++w.cw;
          v = c;
        }
        if (phase == ccw && pred_s == v) {
          phase = cw;  // s->v is an outer edge: the rest lies clockwise from v0
          v = v0;
        }
        if (phase == cw && pred[v] == i) phase = done;  // v->s is an outer edge: complete
        if (phase >= done) break;
        if constexpr (!ReadsInbox) break;
        c = inbox.apex(i, v, phase == ccw);
        if (c < 0) break;
        ++work;  // a step taken from the inbox: one unit
      }
      if (phase >= done) break;
      // The next edge: s->v counter-clockwise, v->s clockwise.
      const double2 pv = load_site(g.points, v);
      pa = phase == ccw ? ps : pv;
      pb = phase == ccw ? pv : ps;
      best = -1;
      best_p = ps;
      visited = {kNone, kNone, -kNone, -kNone};
      bounds.apex = true;
      bounds.disc = false;
      bounds.a = pa;
      bounds.b = pb;
      // First box: a guess at where the empty circle lies, half-width first_reach |ab|_1 / 2
      // around the point first_offset |ab| / 2 left of the midpoint (any box is correct).
      const double bax = pb.x - pa.x, bay = pb.y - pa.y;
      const double lean = 0.5 * g.first_offset;
      const double cx = 0.5 * (pa.x + pb.x) - lean * bay, cy = 0.5 * (pa.y + pb.y) + lean * bax;
      const double r = 0.5 * g.first_reach * (fabs(bax) + fabs(bay));
      target = cells_of(g, cx - r, cy - r, cx + r, cy + r);
      // A long edge (its box over kLongEdgeCells cells) along the side of a grid of equal cells
      // first scans the cells along it: such an edge runs beside a straight hull side, where the
      // empty circle is a sliver along the edge, and the guess's box, as wide as the edge is
      // long, held thousands of sites inside the hull. (Quantile cells' outer rows hold a
      // clustered input's sparse tails, whose long edges are no slivers.)
      if (Strips && g.strips.ids && !g.xb && box_cells(target) > kLongEdgeCells) {
        const CellBox along = cells_of(g, fmin(pa.x, pb.x), fmin(pa.y, pb.y), fmax(pa.x, pb.x), fmax(pa.y, pb.y));
        if (along.x1 <= 1 || along.y1 <= 1 || along.x0 >= g.gx - 2 || along.y0 >= g.gy - 2) target = along;
      }
      begin_target();
      big_scan = box_cells(target) > kBigScanCells;
    }
    if (work > budget) {
      reason = DeferReason::undecided;
      phase = deferred;
    }
    if (phase >= done) break;

    // Decide the pending candidate exactly, then resume the scan after it.
    if constexpr (FirstPass) {
      w.handed_on = true;
      reason = DeferReason::undecided;
      break;
    }
    const int ip = pending;
    const int verdict = decide_exactly(g.points, phase == nearest, i, phase == cw ? v : i, phase == cw ? i : v, best, ip);
    if (verdict == 2) {
      reason = DeferReason::undecided;
      break;
    }
    if (verdict == 1) {
      best = ip;
      best_p = load_site(g.points, ip);
      best_d2 = dist2(pa, best_p);  // in the search's frame, as judge forms it (a = s when nearest)
    }
    slot = ((Strips && strip >= 0) || scanning_across()) ? slot + 1 : static_cast<std::uint32_t>(ip) + 1;
    pending = -1;
  }
  w.predicates = predicates;
  w.work = work;
  w.ok = phase == done;
  w.reason = w.ok ? DeferReason::none : reason;
  return w;
}

/// How a per-site star's searches visit the grid: rings of cells around each edge (walk_star)
/// or box scans (walk_star_boxes). Both find the same stars; the kernels scan boxes, and the host
/// tests walk rings too, as a second search to compare with.
enum class StarSearch { rings, boxes };

/// Work (cells or row segments, plus sites, visited by one site's walk) past which a site
/// defers to the seam stage. A box scan's unit is cheaper than a ring's cell, and the
/// hull-hugging sites of uniform inputs legitimately scan whole columns of the grid, edge after
/// edge; but the kernel lasts as long as its costliest site, which grows faster than the grid:
/// counted on uniform sites, 49,482 units at 10^6, 397,425 at 4 * 10^6, over 2^20 for one
/// 4096^2 set on the H100 (star kernel 487 ms there, against 231 ms for another seed). 2^16
/// defers none of 10^6 uniform sites and a handful beyond; the seam stage makes their triangles.
EXPANSE_HOST_DEVICE unsigned default_budget(StarSearch search) {
  return search == StarSearch::boxes ? 1u << 16 : 1u << 14;
}

template <StarSearch Search, bool ExactLattice = false, bool FirstPass = false, bool ReadsInbox = false,
          bool Strips = false, GridKind Cells = GridKind::any>
EXPANSE_DEVICE_FORCE StarWalk walk_star_by(const GridView& g, const int* pred, int i, int* row, unsigned budget,
                                           const StarInbox& inbox = {}) {
  if constexpr (Search == StarSearch::boxes)
    return walk_star_boxes<Walker::thread, ExactLattice, FirstPass, ReadsInbox, Strips, Cells>(g, pred, i, row, budget,
                                                                                                inbox);
  else
    return walk_star(g, pred, i, row, budget);
}

}  // namespace expanse::detail::cuda
