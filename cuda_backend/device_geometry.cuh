#pragma once
// Device-side geometry shared by the per-site and the block layouts: exact predicates with
// CGAL's perturbation, the uniform bucket grid, the nearest-neighbour search and the apex
// search. Everything a kernel decides here is exact; what it cannot decide it reports as
// `uncertain` and the caller defers the work to the CPU seam stage.
#include <cstdint>
#include <cstring>

#include "device_compat.cuh"
#include "quantile_guide.hpp"
#include "predicates/exact_arith.hpp"

namespace expanse::detail::cuda {

namespace ex = ::expanse::detail::exact;

EXPANSE_DEVICE_FORCE bool safe_point(double2 p) {
  return ex::in_safe_range(p.x) && ex::in_safe_range(p.y);
}

/// Exact orientation: filter, certificate, then (small) expansions. Only the expansion step
/// needs coordinates in the safe range; outside it the answer is `uncertain`.
EXPANSE_DEVICE int orient(double2 a, double2 b, double2 c) {
  int s = ex::orient2d_filter(a.x, a.y, b.x, b.y, c.x, c.y);
  if (s != ex::uncertain) return s;
  s = ex::orient2d_certified(a.x, a.y, b.x, b.y, c.x, c.y);
  if (s != ex::uncertain) return s;
  if (safe_point(a) && safe_point(b) && safe_point(c))
    return ex::orient2d_expansion(a.x, a.y, b.x, b.y, c.x, c.y);
  return ex::uncertain;
}

EXPANSE_DEVICE_FORCE bool lex_less(double2 p, double2 q) {
  return p.x < q.x || (p.x == q.x && p.y < q.y);
}

/// incircle_perturbed's answer where a, b, c, d are exactly cocircular (CCW a, b, c): CGAL's
/// symbolic perturbation, which walks the four points from the lexicographically largest down.
/// `orient` is exact orientation (or `uncertain`).
template <class Orient>
EXPANSE_DEVICE_FORCE int cocircular_perturbed_by(double2 a, double2 b, double2 c, double2 d, Orient orient) {
  const double2 p[4] = {a, b, c, d};
  int order[4] = {0, 1, 2, 3};
  for (int i = 1; i < 4; ++i)
    for (int j = i; j > 0 && lex_less(p[order[j]], p[order[j - 1]]); --j) {
      const int t = order[j];
      order[j] = order[j - 1];
      order[j - 1] = t;
    }
  for (int i = 3; i > 1; --i) {
    const int k = order[i];
    if (k == 3) return -1;
    int o;
    if (k == 2)
      o = orient(a, b, d);
    else if (k == 1)
      o = orient(a, d, c);
    else
      o = orient(d, b, c);
    if (o == ex::uncertain) return ex::uncertain;
    if (o != 0) return o;
  }
  return -1;
}

EXPANSE_DEVICE int cocircular_perturbed(double2 a, double2 b, double2 c, double2 d) {
  return cocircular_perturbed_by(a, b, c, d, [](double2 p, double2 q, double2 r) { return orient(p, q, r); });
}

/// orient2d's sign where its arithmetic is exact (small integer lattices, exact_lattice.hpp:
/// each product is at most 2 D^2 units): no filter, certificate or expansion, so the lattice
/// search keeps the exact arithmetic's registers out of its scan.
EXPANSE_DEVICE_FORCE int orient_on_lattice(double2 a, double2 b, double2 c) {
  const double det = ex::sub(ex::mul(ex::sub(a.x, c.x), ex::sub(b.y, c.y)), ex::mul(ex::sub(a.y, c.y), ex::sub(b.x, c.x)));
  return det > 0.0 ? 1 : det < 0.0 ? -1 : 0;
}

/// CGAL's Delaunay_triangulation_2::side_of_oriented_circle(a, b, c, d, perturb = true) for
/// CCW (a, b, c): +1 if d is inside the perturbed circle, -1 outside, or `uncertain`. The full
/// incircle expansion needs ~40 KB of stack per thread, too much to reserve for every resident
/// GPU thread; its form for exact coordinate differences (incircle_exact_differences_grown, 320
/// bytes) decides nearby sites of one magnitude, nearly cocircular float inputs among them. An
/// incircle that neither the filter, the certificate nor that decides is deferred.
EXPANSE_DEVICE int incircle_perturbed(double2 a, double2 b, double2 c, double2 d) {
  int s = ex::incircle_filter(a.x, a.y, b.x, b.y, c.x, c.y, d.x, d.y);
  if (s == ex::uncertain) s = ex::incircle_certified(a.x, a.y, b.x, b.y, c.x, c.y, d.x, d.y);
  if (s == ex::uncertain) s = ex::incircle_exact_differences_grown(a.x, a.y, b.x, b.y, c.x, c.y, d.x, d.y);
  if (s != 0) return s;  // a sign, or uncertain
  return cocircular_perturbed(a, b, c, d);
}

/// A quantile axis' guide (quantile_guide.hpp): its key and its table, first[k] the
/// number of column boundaries in bins below k. None (first == nullptr): the full binary search.
/// H100, 4096^2 uniform: cells looked up by 12-step binary searches cost the star kernel about a
/// third of its time.
struct QuantileGuide {
  const int* first = nullptr;
  QuantileGuideKey key;

  /// Narrows [*lo, *hi] to the columns that can hold v: those between the counts of v's bin and
  /// of the next.
  EXPANSE_DEVICE_FORCE void narrow(double v, int* lo, int* hi) const {
    const int k = quantile_guide_bin(key, v);
    *lo = load_readonly(first + k);
    *hi = load_readonly(first + k + 1);
  }
};

/// The grid's two outermost columns and rows on each side, their sites in order of a key that
/// grows inwards: the left strip (columns 0 and 1) by x, the right (the last two columns) by -x,
/// the bottom (rows 0 and 1) by y, the top (the last two rows) by -y. A search whose region lies
/// in one of them and runs along it (hull-hugging sites beside a straight side of the hull:
/// circles through nearly collinear sites, whose region is a sliver along the whole side) tests
/// only the strip's sites up to the region's inner bound instead of every row of the side
/// (star_scan.cuh). Built by boundary_strips_kernel (star_kernels.cu) or the host mirror
/// (star_host.hpp); no strips: ids null.
enum StripSide : int { kStripLeft = 0, kStripRight = 1, kStripBottom = 2, kStripTop = 3 };
struct BoundaryStrips {
  const std::uint32_t* keys = nullptr;  ///< side s: keys[s * capacity + k], ascending (strip_key)
  const int* ids = nullptr;             ///< the sites (local ids), in the same order
  const int* length = nullptr;          ///< length[s]: the sites in side s (0: that side has none)
  int capacity = 0;
};

/// A key monotone in the coordinate c (c <= c' gives strip_key(c) <= strip_key(c')): c rounded to
/// float (rounding is monotone) and its bits ordered as unsigned integers. A strip sorted by these
/// keys holds every site with coordinate <= c before its first key above strip_key(c): exact, for
/// half the sort's passes of the doubles themselves.
EXPANSE_HOST_DEVICE std::uint32_t strip_key(double c) {
  const float f = static_cast<float>(c);
  std::uint32_t u;
  std::memcpy(&u, &f, sizeof u);
  return (u & 0x80000000u) ? ~u : (u | 0x80000000u);
}

/// Room for each side's sites: a side holds two rows or columns of cells, two to four sites a
/// cell on average; a side with more (a cluster against the box's edge) has no strip (length 0).
/// Grids under 4 x 4 cells have none.
EXPANSE_HOST_DEVICE int strip_capacity(int gx, int gy) { return 16 * (gx > gy ? gx : gy); }
EXPANSE_HOST_DEVICE bool strips_fit(int gx, int gy) { return gx >= 4 && gy >= 4; }
/// The cells of side s, and the j-th of them (in cell order, as the strip gathers its sites).
EXPANSE_HOST_DEVICE int strip_cells(int s, int gx, int gy) {
  return 2 * (s == kStripLeft || s == kStripRight ? gy : gx);
}
EXPANSE_HOST_DEVICE int strip_cell(int s, int j, int gx, int gy) {
  return s == kStripLeft    ? (j >> 1) * gx + (j & 1)
         : s == kStripRight ? (j >> 1) * gx + gx - 2 + (j & 1)
         : s == kStripBottom ? j
                             : (gy - 2) * gx + j;
}
/// The coordinate that grows inwards from side s.
EXPANSE_HOST_DEVICE double strip_coordinate(int s, double2 p) {
  return s == kStripLeft ? p.x : s == kStripRight ? -p.x : s == kStripBottom ? p.y : -p.y;
}

/// How many of side s's sites have keys at most `key` (a binary search).
EXPANSE_DEVICE_FORCE int strip_prefix(const BoundaryStrips& strips, int s, std::uint32_t key) {
  const std::uint32_t* keys = strips.keys + static_cast<std::size_t>(s) * strips.capacity;
  int lo = 0, hi = load_readonly(strips.length + s);
  while (lo < hi) {
    const int m = (lo + hi) >> 1;
    if (load_readonly(keys + m) <= key) lo = m + 1;
    else hi = m;
  }
  return lo;
}

/// The outer columns of a quantile grid whose x-axis has heavy tails, their sites column after
/// column (tail_columns_width of them on each side; within a column row after row, within a cell
/// in the grid's order). The grid's cells are sorted row-major, so a box scan costs a row
/// segment a row; a radial cluster's x-tails (kuzmin) sit in wide columns that its dense centre
/// cuts into thin rows, and their searches' boxes run hundreds of nearly empty rows tall and a
/// few columns wide. Such a box, lying in one side's columns, is scanned here a column at a time
/// (star_scan.cuh): the same cells, the same sites, a segment a column. Counted on the CPU
/// (kuzmin 4096^2, two phases, first-pass budget 2^11), the sites of the outer 128 columns on
/// each side, in rows away from the y-tails, held 11% of the phases' lock-step work for 1% of
/// the sites; the y-tails' sites, whose boxes are wide and short, held under 1%. Built by
/// build_tail_columns (star_kernels.cu) or the host mirror (star_host.hpp); none: ids null.
struct TailColumns {
  /// Column j of the copy (tail_column_index), rows r .. r': sites [start[j gy + r], start[j gy + r' + 1]).
  const std::uint32_t* start = nullptr;
  const int* ids = nullptr;  ///< the sites (local ids), in the copy's order
  int width = 0;             ///< columns on each side
};

/// Columns on each side that a grid of gx columns copies: the outer eighth (quantile cells give
/// a heavy tail five times its share of columns, so about its outer 2.5% of sites), none under
/// 16 columns.
EXPANSE_HOST_DEVICE int tail_columns_width(int gx) { return gx >= 16 ? gx / 8 : 0; }
/// Grid column x's column in the copy (x within `width` of either side), and the other way round.
EXPANSE_HOST_DEVICE int tail_column_index(int x, int gx, int width) { return x < width ? x : x - (gx - 2 * width); }
EXPANSE_HOST_DEVICE int tail_column_of_grid(int j, int gx, int width) { return j < width ? j : j + (gx - 2 * width); }

/// A grid of buckets over a box: sites sorted by cell, cell_start[c]..cell_start[c+1] the sites
/// of cell c (indices into the sorted arrays). Two kinds, one interface:
///  - uniform (xb == nullptr): cell_x is a rounded affine map, monotone;
///  - quantile (xb, yb set): column j holds exactly the x with xb[j] <= x < xb[j+1] (xb[0] and
///    xb[gx] are never read), boundaries taken from sample quantiles, so clustered inputs
///    (kuzmin, gaussian) do not pile thousands of sites into one cell. cell_x is a binary search,
///    narrowed by a guide when one is set (QuantileGuide).
struct GridView {
  double min_x, min_y;
  double inv_w, inv_h;    ///< cells per unit length (uniform kind)
  double cell_w, cell_h;  ///< unit lengths per cell (uniform kind)
  int gx, gy;
  const std::uint32_t* cell_start;
  const double2* points;  ///< sorted by cell
  const double* xb = nullptr;  ///< quantile kind: gx + 1 column boundaries
  const double* yb = nullptr;
  double max_x = 0.0, max_y = 0.0;  ///< bounding box of the sites (cell bounds clamp to it)
  QuantileGuide x_guide, y_guide;  ///< quantile kind, optional: where to start searching
  /// An apex search's first box (star_scan.cuh): half-width first_reach * |ab|_1 / 2 around the
  /// point first_offset * |ab| / 2 left of the edge's midpoint (first_box_shape in star_grid.hpp).
  double first_reach = 1.0, first_offset = 1.0;
  BoundaryStrips strips;  ///< optional (strips.ids null: none)
  TailColumns tail;       ///< optional (tail.ids null: none)

  // The same monotone function buckets the sites and converts search boxes to cells, so no
  // rounding can hide a site: x <= x' implies cell_x(x) <= cell_x(x').
  EXPANSE_DEVICE_FORCE static int upper_index(const double* bounds, double v, int lo, int hi) {
    // Largest j in [lo, hi] with j == 0 or bounds[j] <= v, given that the answer over
    // [0, cells) lies in [lo, hi].
    while (lo < hi) {
      const int m = (lo + hi + 1) >> 1;
      if (load_readonly(bounds + m) <= v) lo = m;
      else hi = m - 1;
    }
    return lo;
  }
  /// Column (row) of v on a quantile axis: the full binary search, or the guided one.
  EXPANSE_DEVICE_FORCE static int quantile_index(const double* bounds, int cells, const QuantileGuide& guide,
                                                 double v) {
    int lo = 0, hi = cells - 1;
    if (guide.first) guide.narrow(v, &lo, &hi);
    return upper_index(bounds, v, lo, hi);
  }
  EXPANSE_DEVICE_FORCE int cell_x(double x) const {
    if (xb) return quantile_index(xb, gx, x_guide, x);
    const double t = ex::mul(ex::sub(x, min_x), inv_w);
    if (!(t >= 0.0)) return 0;
    if (t >= static_cast<double>(gx - 1)) return gx - 1;
    return static_cast<int>(t);
  }
  EXPANSE_DEVICE_FORCE int cell_y(double y) const {
    if (yb) return quantile_index(yb, gy, y_guide, y);
    const double t = ex::mul(ex::sub(y, min_y), inv_h);
    if (!(t >= 0.0)) return 0;
    if (t >= static_cast<double>(gy - 1)) return gy - 1;
    return static_cast<int>(t);
  }
  // Conservative real bounds of a cell: every site bucketed into column x has lo <= p.x <= hi.
  EXPANSE_DEVICE_FORCE void x_bounds(int x, double* lo, double* hi) const {
    if (xb) {
      *lo = x == 0 ? min_x : load_readonly(xb + x);
      *hi = x == gx - 1 ? max_x : load_readonly(xb + x + 1);
      return;
    }
    const double l = min_x + x * cell_w, h = min_x + (x + 1) * cell_w;
    const double slop = 1e-9 * (cell_w + fabs(l) + fabs(h));
    *lo = x == 0 ? min_x : l - slop;
    *hi = x == gx - 1 ? max_x : h + slop;
  }
  EXPANSE_DEVICE_FORCE void y_bounds(int y, double* lo, double* hi) const {
    if (yb) {
      *lo = y == 0 ? min_y : load_readonly(yb + y);
      *hi = y == gy - 1 ? max_y : load_readonly(yb + y + 1);
      return;
    }
    const double l = min_y + y * cell_h, h = min_y + (y + 1) * cell_h;
    const double slop = 1e-9 * (cell_h + fabs(l) + fabs(h));
    *lo = y == 0 ? min_y : l - slop;
    *hi = y == gy - 1 ? max_y : h + slop;
  }
};

/// A grid's kind as a walk's code knows it: `any` decides by GridView::xb at every look-up;
/// `uniform` walks a copy whose quantile boundaries are null constants, so that the compiler
/// drops the quantile look-ups; `guided` (quantile cells with both guides) one that the
/// compiler is told has them, so that it drops the uniform cells' arithmetic and the unguided
/// binary search; `guided_tails` the same with TailColumns, whose scans across only its walks
/// compile (in every walk they cost inputs that have no such columns 1.5 ms at 4096^2: H100,
/// gaussian). The caller must know which kind the grid is.
enum class GridKind { any, uniform, guided, guided_tails };

template <GridKind Kind>
EXPANSE_DEVICE_FORCE GridView of_kind(const GridView& g) {
  GridView v = g;
  if constexpr (Kind == GridKind::uniform) {
    v.xb = nullptr;
    v.yb = nullptr;
    v.tail.ids = nullptr;
  }
#if defined(__CUDA_ARCH__)
  if constexpr (Kind != GridKind::guided_tails) v.tail.ids = nullptr;
  if constexpr (Kind == GridKind::guided || Kind == GridKind::guided_tails)
    __builtin_assume(v.xb != nullptr && v.yb != nullptr && v.x_guide.first != nullptr && v.y_guide.first != nullptr);
  if constexpr (Kind == GridKind::guided_tails) __builtin_assume(v.tail.ids != nullptr);
#endif
  return v;
}

/// The kind a walk on `g` may be compiled for.
EXPANSE_DEVICE_FORCE GridKind kind_of(const GridView& g) {
  if (!g.xb) return GridKind::uniform;
  if (!g.x_guide.first || !g.y_guide.first) return GridKind::any;
  return g.tail.ids ? GridKind::guided_tails : GridKind::guided;
}


/// Exact comparison of |s - p|^2 with |s - q|^2: -1, 0, +1, or uncertain.
EXPANSE_DEVICE int compare_distance(double2 s, double2 p, double2 q) {
  if (!(safe_point(s) && safe_point(p) && safe_point(q))) return ex::uncertain;
  const auto pdx = ex::exact_difference(p.x, s.x), pdy = ex::exact_difference(p.y, s.y);
  const auto qdx = ex::exact_difference(q.x, s.x), qdy = ex::exact_difference(q.y, s.y);
  const auto dp = pdx * pdx + pdy * pdy;
  const auto dq = qdx * qdx + qdy * qdy;
  return (dp - dq).sign();
}

EXPANSE_DEVICE_FORCE double dist2(double2 s, double2 p) {
  const double dx = ex::sub(p.x, s.x), dy = ex::sub(p.y, s.y);
  return ex::add(ex::mul(dx, dx), ex::mul(dy, dy));
}

/// Visits the cells of ring k (Chebyshev distance k from (cx, cy)) clipped to [x0,x1]x[y0,y1],
/// row by row. One loop nest and one call of f: f is inlined once, so threads of a warp that are
/// in different parts of their rings still run the same instructions (four call sites, one per
/// side, made four copies of the whole search body for divergent threads to serialise over).
template <class F>
EXPANSE_DEVICE_FORCE void for_ring(int cx, int cy, int k, int x0, int x1, int y0, int y1, F&& f) {
  const int ylo = max(cy - k, y0), yhi = min(cy + k, y1);
  const int xlo = max(cx - k, x0), xhi = min(cx + k, x1);
  for (int y = ylo; y <= yhi; ++y) {
    // Top and bottom rows whole; other rows only their two end cells (one when k == 0).
    const bool edge_row = y == cy - k || y == cy + k;
    const int step = edge_row ? 1 : max(1, 2 * k);
    for (int x = edge_row ? xlo : cx - k; x <= xhi; x += step) {
      if (x < x0) continue;
      f(x, y);
    }
  }
}

/// Exact nearest neighbour of sorted site `self` (ties between exactly equal distances go to
/// the smaller index). Returns -1 with *ok = false when a comparison cannot be decided or the
/// search spends more than `budget` units of work (cells + sites, counted in *work).
EXPANSE_DEVICE int nearest_site(const GridView& g, int self, double2 s, bool* ok, unsigned* work = nullptr,
                                   unsigned budget = 0xffffffffu) {
  const int cx = g.cell_x(s.x), cy = g.cell_y(s.y);
  unsigned local_work = 0;
  unsigned* w = work ? work : &local_work;
  int best = -1;
  double best_d = 0.0;
  double2 best_p = s;
  const int kmax = max(g.gx, g.gy);
  for (int k = 0; k <= kmax; ++k) {
    for_ring(cx, cy, k, 0, g.gx - 1, 0, g.gy - 1, [&](int x, int y) {
      if (!*ok) return;
      const int c = y * g.gx + x;
      const std::uint32_t begin = g.cell_start[c], end = g.cell_start[c + 1];
      *w += 1 + (end - begin);
      if (*w > budget) { *ok = false; return; }
      for (std::uint32_t j = begin; j < end; ++j) {
        if (static_cast<int>(j) == self) continue;
        const double2 p = g.points[j];
        const double d = dist2(s, p);
        bool take;
        if (best < 0) {
          take = true;
        } else if (d < best_d * (1.0 - 16.0 * ex::epsilon)) {
          take = true;
        } else if (d > best_d * (1.0 + 16.0 * ex::epsilon)) {
          take = false;
        } else {
          const int cmp = compare_distance(s, p, best_p);
          if (cmp == ex::uncertain) {
            *ok = false;
            return;
          }
          take = cmp < 0 || (cmp == 0 && static_cast<int>(j) < best);
        }
        if (take) {
          best = static_cast<int>(j);
          best_d = d;
          best_p = p;
        }
      }
    });
    if (!*ok) return -1;
    if (cx - k <= 0 && cx + k >= g.gx - 1 && cy - k <= 0 && cy + k >= g.gy - 1) break;  // all visited
    if (best >= 0) {
      // Unvisited sites lie outside the visited square of cells: at least `gap` away.
      double lo, hi, gap = 1e308;
      if (cx - k > 0) { g.x_bounds(cx - k, &lo, &hi); gap = fmin(gap, s.x - lo); }
      if (cx + k < g.gx - 1) { g.x_bounds(cx + k, &lo, &hi); gap = fmin(gap, hi - s.x); }
      if (cy - k > 0) { g.y_bounds(cy - k, &lo, &hi); gap = fmin(gap, s.y - lo); }
      if (cy + k < g.gy - 1) { g.y_bounds(cy + k, &lo, &hi); gap = fmin(gap, hi - s.y); }
      if (sqrt(best_d) * (1.0 + 1e-9) < gap * (1.0 - 1e-9)) break;
    }
  }
  return best;
}

/// circle(a, b, c) ∩ closed left half-plane of a->b, conservatively: a box, and a disc
/// (centre, reach) holding the circle. Floating point with a proven-generous margin; for a nearly
/// flat triangle (rounded determinant within its error bound) the determinant is evaluated
/// exactly and rounded once (cf. the host's apex_search.cpp), so near-collinear sites still get
/// a tight region instead of "search everything". False if even that cannot be bounded; the
/// caller then keeps the previous (larger) region.
struct CircleRegion {
  double x_lo, x_hi, y_lo, y_hi;
  double ox, oy, reach;
};

/// The disc with diameter a-b, when c provably sees a-b at an obtuse angle: then every point of
/// circle(a, b, c) ∩ left half-plane (the minor segment) sees a-b at an angle at least as wide,
/// so it lies in this disc (Thales). Hull-hugging slivers of uniform inputs are this case: their
/// circumcircles are huge and, with rounding margins, their boxes spanned the whole grid.
EXPANSE_DEVICE bool thales_region(double2 a, double2 b, double2 c, CircleRegion* out) {
  constexpr double eps = ex::epsilon;
  const double acx = a.x - c.x, acy = a.y - c.y, bcx = b.x - c.x, bcy = b.y - c.y;
  const double dot = acx * bcx + acy * bcy;
  const double lac = sqrt(acx * acx + acy * acy), lbc = sqrt(bcx * bcx + bcy * bcy);
  const double scale = fabs(a.x) + fabs(a.y) + fabs(b.x) + fabs(b.y) + fabs(c.x) + fabs(c.y);
  if (!(dot < -(1e-6 * lac * lbc + 16.0 * eps * scale * (lac + lbc)))) return false;
  const double bx = b.x - a.x, by = b.y - a.y;
  const double half = 0.5 * sqrt(bx * bx + by * by);
  const double ox = 0.5 * a.x + 0.5 * b.x, oy = 0.5 * a.y + 0.5 * b.y;
  const double reach = half * (1.0 + 1e-6) + 8.0 * eps * (fabs(ox) + fabs(oy) + half) + 1e-300;
  if (!isfinite(reach)) return false;
  out->ox = ox;
  out->oy = oy;
  out->reach = reach;
  out->x_lo = ox - reach;
  out->x_hi = ox + reach;
  out->y_lo = oy - reach;
  out->y_hi = oy + reach;
  return true;
}

/// circle(a, b, c) ∩ left half-plane bounded by the circumcircle's cap (below) and, where it
/// applies, by the Thales disc; both are supersets of the region, so their boxes intersect and
/// the smaller disc is kept.
EXPANSE_DEVICE bool circumcircle_region(double2 a, double2 b, double2 c, CircleRegion* out);

EXPANSE_DEVICE bool circle_region(double2 a, double2 b, double2 c, CircleRegion* out) {
  CircleRegion cap, thales;
  const bool has_cap = circumcircle_region(a, b, c, &cap);
  const bool has_thales = thales_region(a, b, c, &thales);
  if (!has_cap && !has_thales) return false;
  if (!has_thales) {
    *out = cap;
    return true;
  }
  if (!has_cap) {
    *out = thales;
    return true;
  }
  *out = cap.reach <= thales.reach ? cap : thales;
  out->x_lo = fmax(cap.x_lo, thales.x_lo);
  out->x_hi = fmin(cap.x_hi, thales.x_hi);
  out->y_lo = fmax(cap.y_lo, thales.y_lo);
  out->y_hi = fmin(cap.y_hi, thales.y_hi);
  return true;
}

EXPANSE_DEVICE bool circumcircle_region(double2 a, double2 b, double2 c, CircleRegion* out) {
  constexpr double eps = ex::epsilon;
  const double bx = b.x - a.x, by = b.y - a.y, cx = c.x - a.x, cy = c.y - a.y;
  const double bb = bx * bx + by * by, cc = cx * cx + cy * cy;
  const double t1 = bx * cy, t2 = by * cx;
  double d = t1 - t2;
  double ed = 16.0 * eps * (fabs(t1) + fabs(t2));
  if (!(fabs(d) > 4.0 * ed)) {
    // Nearly flat: the rounded determinant is noise. When the coordinate differences are exact
    // (always, for sites closer than their magnitude), evaluate it exactly as a sum of
    // error-free products and round once: a few doubles, where full expansions of the
    // numerators would cost kilobytes of stack per GPU thread. The numerators need no such
    // care: their rounding error stays a few ulps of the radius.
    if (!(safe_point(a) && safe_point(b) && safe_point(c))) return false;
    double e1, e2, e3, e4;
    ex::two_diff(b.x, a.x, e1);
    ex::two_diff(b.y, a.y, e2);
    ex::two_diff(c.x, a.x, e3);
    ex::two_diff(c.y, a.y, e4);
    if (e1 != 0.0 || e2 != 0.0 || e3 != 0.0 || e4 != 0.0) return false;
    double l1, l2, l0;
    const double h1 = ex::two_product(bx, cy, l1), h2 = ex::two_product(by, cx, l2);
    const double dh = ex::two_diff(h1, h2, l0);
    const double rest = ex::add(l0, ex::sub(l1, l2));
    d = ex::add(dh, rest);
    ed = 4.0 * eps * (fabs(l0) + fabs(l1) + fabs(l2)) + 2.0 * eps * fabs(d);
  }
  const double ad = fabs(d);
  if (!(ad > 4.0 * ed) || !(ad > 1e-280)) return false;
  const double nx = cy * bb - by * cc, ny = bx * cc - cx * bb;
  const double enx = 16.0 * eps * (fabs(cy) * bb + fabs(by) * cc);
  const double eny = 16.0 * eps * (fabs(bx) * cc + fabs(cx) * bb);
  const double ux = nx / (2.0 * d), uy = ny / (2.0 * d);
  // |d_true| >= 0.75 |d|: the quotient's error is at most (e_n + 2|u| e_d) / (1.5 |d|).
  const double eux = (enx + 2.0 * fabs(ux) * ed) / (1.5 * ad) + 4.0 * eps * fabs(ux);
  const double euy = (eny + 2.0 * fabs(uy) * ed) / (1.5 * ad) + 4.0 * eps * fabs(uy);
  if (!isfinite(ux) || !isfinite(uy) || !isfinite(eux + euy)) return false;
  const double ox = a.x + ux, oy = a.y + uy;
  const double r = sqrt(ux * ux + uy * uy);
  const double m = 2.0 * (eux + euy) + 8.0 * eps * (fabs(a.x) + fabs(a.y) + r) + 1e-300;
  const double rr = r + 2.0 * m;
  if (!isfinite(rr)) return false;
  double xl = fmin(a.x, b.x), xh = fmax(a.x, b.x), yl = fmin(a.y, b.y), yh = fmax(a.y, b.y);
  const double ex_x[4] = {ox + rr, ox - rr, ox, ox};
  const double ex_y[4] = {oy, oy, oy + rr, oy - rr};
  const double len = fabs(bx) + fabs(by);
  for (int i = 0; i < 4; ++i) {
    const double px = ex_x[i] - a.x, py = ex_y[i] - a.y;
    const double side = bx * py - by * px;
    const double tol = len * 4.0 * m + 8.0 * eps * (fabs(bx * py) + fabs(by * px));
    if (side > -tol) {
      xl = fmin(xl, ex_x[i]);
      xh = fmax(xh, ex_x[i]);
      yl = fmin(yl, ex_y[i]);
      yh = fmax(yh, ex_y[i]);
    }
  }
  out->x_lo = xl - m;
  out->x_hi = xh + m;
  out->y_lo = yl - m;
  out->y_hi = yh + m;
  out->ox = ox;
  out->oy = oy;
  out->reach = (rr + m) * (1.0 + 1e-12);
  return true;
}

/// The box part of circle_region (the block layout's acceptance test).
EXPANSE_DEVICE bool cap_box(double2 a, double2 b, double2 c, double* x_lo, double* x_hi,
                               double* y_lo, double* y_hi) {
  CircleRegion r;
  if (!circle_region(a, b, c, &r)) return false;
  *x_lo = r.x_lo;
  *x_hi = r.x_hi;
  *y_lo = r.y_lo;
  *y_hi = r.y_hi;
  return true;
}

enum ApexStatus : int { apex_found = 0, apex_none = 1, apex_uncertain = 2 };

/// apex(a->b) over the grid's sites: the site c strictly left of a->b whose circle(a, b, c)
/// holds no other site under CGAL's perturbation. Rings of cells around the edge's midpoint,
/// clipped to the cell range of the current candidate's region box; a cell is skipped when it
/// lies entirely right of a->b or outside the candidate's circle (a better candidate only
/// shrinks circle ∩ left half-plane, so pruning is safe for good). Stops once the visited square
/// covers the region box. Candidate ids are indices into g.points.
/// *predicates counts the orient2d and incircle evaluations (for the benchmark's floor count);
/// *work counts cells + sites visited; past `budget` the search gives up (apex_uncertain).
EXPANSE_DEVICE int find_apex(const GridView& g, int ia, double2 a, int ib, double2 b, int* status,
                                unsigned* predicates, unsigned* work, unsigned budget) {
  const double2 mid = make_double2(0.5 * a.x + 0.5 * b.x, 0.5 * a.y + 0.5 * b.y);
  const int mx = g.cell_x(mid.x), my = g.cell_y(mid.y);
  int rx0 = 0, rx1 = g.gx - 1, ry0 = 0, ry1 = g.gy - 1;
  int best = -1;
  double2 bp = a;
  bool failed = false, has_circle = false;
  CircleRegion region{};
  const double ex_ = b.x - a.x, ey_ = b.y - a.y;
  const int kmax = max(g.gx, g.gy);
  for (int k = 0; k <= kmax; ++k) {
    for_ring(mx, my, k, rx0, rx1, ry0, ry1, [&](int x, int y) {
      if (failed) return;
      // The region may have shrunk since the ring started.
      if (x < rx0 || x > rx1 || y < ry0 || y > ry1) return;
      if (k > 0) {
        double xl, xh, yl, yh;
        g.x_bounds(x, &xl, &xh);
        g.y_bounds(y, &yl, &yh);
        // Entirely right of a->b: the largest cross product over the cell is at one corner.
        const double px = (ey_ < 0 ? xh : xl) - a.x, py = (ex_ > 0 ? yh : yl) - a.y;
        const double cross = ex_ * py - ey_ * px;
        if (cross < -1e-9 * (fabs(ex_) + fabs(ey_)) * (fabs(px) + fabs(py))) return;
        if (has_circle) {
          const double dx = fmax(fmax(xl - region.ox, 0.0), region.ox - xh);
          const double dy = fmax(fmax(yl - region.oy, 0.0), region.oy - yh);
          if (dx * dx + dy * dy > region.reach * region.reach * (1.0 + 1e-9)) return;
        }
      }
      const int c = y * g.gx + x;
      const std::uint32_t begin = g.cell_start[c], end = g.cell_start[c + 1];
      // A search that runs away would hold its whole warp; past the budget the site defers and
      // the seam stage makes its triangles.
      *work += 1 + (end - begin);
      if (*work > budget) { failed = true; return; }
      bool improved = false;
      for (std::uint32_t j = begin; j < end; ++j) {
        const int id = static_cast<int>(j);
        if (id == ia || id == ib) continue;
        const double2 p = g.points[j];
        const int o = orient(a, b, p);
        ++*predicates;
        if (o == ex::uncertain) { failed = true; return; }
        if (o <= 0) continue;
        if (best >= 0) {
          const int in = incircle_perturbed(a, b, bp, p);
          ++*predicates;
          if (in == ex::uncertain) { failed = true; return; }
          if (in <= 0) continue;
        }
        best = id;
        bp = p;
        improved = true;
      }
      if (improved) {
        CircleRegion r;
        // If even the exact circumcentre cannot bound it, the previous region (a superset) stays.
        if (circle_region(a, b, bp, &r)) {
          region = r;
          has_circle = true;
          rx0 = max(rx0, g.cell_x(r.x_lo));
          rx1 = min(rx1, g.cell_x(r.x_hi));
          ry0 = max(ry0, g.cell_y(r.y_lo));
          ry1 = min(ry1, g.cell_y(r.y_hi));
        }
      }
    });
    if (failed) break;
    if (mx - k <= rx0 && mx + k >= rx1 && my - k <= ry0 && my + k >= ry1) break;
  }
  if (failed) {
    *status = apex_uncertain;
    return -1;
  }
  *status = best >= 0 ? apex_found : apex_none;
  return best;
}

}  // namespace expanse::detail::cuda
