#pragma once
// One site's star built from the sites around it, in one scan of their cells: the star pass that
// runs before the walks (star_scan.cuh), for every site off the hull.
//
// The walk finds a star apex by apex, each apex search scanning its own boxes of cells, so a
// site's few dozen nearby candidates are tested edge after edge, through a loop nest whose
// depth differs from thread to thread. Here each candidate is tested once, against the star as
// it stands: the star of s among the sites inserted so far, kept as its neighbours in
// counter-clockwise order. Inserting p is Bowyer-Watson's step seen from s: the triangles
// (s, v_j, v_j+1) whose circle holds p form one run j = l .. r, their inner neighbours
// v_l+1 .. v_r leave the star and p takes their place. That run, when it is not empty, holds the
// triangle whose angle at s holds p (the cavity is star-shaped from p and s lies on its
// boundary), so a candidate that changes nothing costs its orientations against the neighbours
// and one incircle test.
//
// It starts from four virtual neighbours (s + (±8, 0), s + (0, ±8), beyond every site: the
// scaled sites lie within [-1, 1]^2), so the star is closed from the start. A star with no
// virtual neighbour left, each of whose circumdiscs lies inside the cells scanned, is s's star
// in the whole set: every site in those cells was inserted, so each disc is empty of all sites,
// and triangles that are Delaunay and go all the way round s are its whole star. Until then the
// scan grows towards the discs. The predicates are the apex search's filters in s's frame
// (apex_filter.hpp); a test they cannot decide hands the site on to the walks, as do hull sites
// (their stars never close), stars of more than kLocalStar neighbours, and sites that spend the
// work budget. So this pass decides nothing the filters do not decide exactly, and what it
// finishes is the walk's star (tests/unit/test_cuda_star_walk.cpp compares them on the CPU).
#include "star_scan.cuh"

namespace expanse::detail::cuda {

/// The most neighbours a star holds while it is built (the virtual four included).
inline constexpr int kLocalStar = 16;
/// Distance of the virtual neighbours from s along each axis (a power of two: exact offsets).
inline constexpr double kVirtualReach = 8.0;

/// s's neighbour `id` in s's frame: a site (id >= 0) less s, or virtual neighbour -1 .. -4 at
/// 0, 90, 180 and 270 degrees.
EXPANSE_DEVICE_FORCE ex::ApexPoint local_neighbour(const GridView& g, double2 s, int id) {
  double x, y;
  if (id >= 0) {
    const double2 v = load_site(g.points, id);
    x = ex::sub(v.x, s.x);
    y = ex::sub(v.y, s.y);
  } else {
    const int k = -id - 1;
    x = k == 0 ? kVirtualReach : k == 2 ? -kVirtualReach : 0.0;
    y = k == 1 ? kVirtualReach : k == 3 ? -kVirtualReach : 0.0;
  }
  return {x, y, ex::add(ex::mul(x, x), ex::mul(y, y))};
}

/// orient2d(s, v, p) from v and p in s's frame (Shewchuk's filter, as apex_orient_signs).
EXPANSE_DEVICE_FORCE ex::FilterSigns local_orient(const ex::ApexPoint& v, const ex::ApexPoint& p) {
  const double left = ex::mul(v.x, p.y), right = ex::mul(v.y, p.x);
  const double k = ex::sub(left, right);
  const double perm = ex::add(ex::magnitude(left), ex::magnitude(right));
  const bool trusted = perm >= 0x1p-974;
  const double bound = ex::mul(ex::orient2d_filter_bound, perm);
  return {trusted && k > bound, trusted && -k > bound};
}

/// incircle(s, v, w, p), all in s's frame: positive when p lies inside the circle of the
/// counter-clockwise triangle (s, v, w).
EXPANSE_DEVICE_FORCE ex::FilterSigns local_incircle(const ex::ApexPoint& v, const ex::ApexPoint& w,
                                                    const ex::ApexPoint& p) {
  const ex::ApexEdge edge{0.0, 0.0, v.x, v.y, v.d2};
  return ex::apex_incircle_signs(ex::apex_lift(edge, w), p);
}

/// The box of the circumdisc of (s, v, w) with its rounding margins, grown into *box; false when
/// it cannot be bounded (nearly flat).
EXPANSE_DEVICE_FORCE bool grow_by_disc(double2 s, double2 v, double2 w, double* box) {
  double ox, oy, rr, m;
  if (!circumcircle_with_margin(s, v, w, &ox, &oy, &rr, &m)) return false;
  const double reach = rr + m;
  box[0] = fmin(box[0], ox - reach);
  box[1] = fmin(box[1], oy - reach);
  box[2] = fmax(box[2], ox + reach);
  box[3] = fmax(box[3], oy + reach);
  return true;
}

/// Builds site i's star in ids[0], ids[stride], ... (kLocalStar entries: on the device a
/// column of shared memory) and, when it is finished, copies it to `row` (the counter-clockwise
/// part of a walk's row: a closed star from index 0). Not finished: ok false and handed_on set,
/// the walks take the site. `work` counts row segments and sites scanned, as the walks do.
EXPANSE_DEVICE StarWalk local_star(const GridView& g, const int* pred, int i, int* ids, int stride, int* row,
                                   unsigned budget) {
  StarWalk w;
  w.handed_on = true;
  if (pred[i] >= 0) return w;  // on the hull: the star never closes
  const double2 s = load_site(g.points, i);
  int k = 4;
  for (int t = 0; t < 4; ++t) ids[t * stride] = -1 - t;
  int virtuals = 4;
  unsigned work = 0, predicates = 0;
  auto hand_on = [&] {
    w.work = work;
    w.predicates = predicates;
    return w;
  };
  // disc_box: a box holding every circumdisc of the star, once it has no virtual neighbour
  // (x_lo, y_lo, x_hi, y_hi); a site outside it is in no disc and changes nothing.
  bool bounded = false;
  double disc_box[4] = {0.0, 0.0, 0.0, 0.0};
  const CellBox whole{0, 0, g.gx - 1, g.gy - 1};
  constexpr int kNone = 1 << 29;
  CellBox visited{kNone, kNone, -kNone, -kNone};
  const int cx = g.cell_x(s.x), cy = g.cell_y(s.y);
  CellBox target{max(cx - 1, 0), max(cy - 1, 0), min(cx + 1, whole.x1), min(cy + 1, whole.y1)};

  // Inserts candidate c at p (s's frame): 0 nothing changes, 1 inserted (at index *at), 2
  // cannot tell.
  auto insert = [&](int c, const ex::ApexPoint& p, int* at) {
    // Where the triangle holding p's direction is: j with p left of (or on) s->v_j and right of
    // (or on) s->v_j+1. Undecided orientations admit both neighbours' triangles.
    ex::ApexPoint first = local_neighbour(g, s, ids[0]);
    ex::FilterSigns o_first = local_orient(first, p);
    ex::FilterSigns o = o_first;
    ex::ApexPoint v = first;
    int hit = -1;
    for (int j = 0; j < k; ++j) {
      const bool last = j + 1 == k;
      const ex::ApexPoint next = last ? first : local_neighbour(g, s, ids[(j + 1) * stride]);
      const ex::FilterSigns o_next = last ? o_first : local_orient(next, p);
      predicates += last ? 0u : 1u;
      if (!o.negative && !o_next.positive) {
        const ex::FilterSigns in = local_incircle(v, next, p);
        ++predicates;
        if (!in.positive && !in.negative) return 2;
        if (in.positive) {
          hit = j;
          break;
        }
        if (o.positive && o_next.negative) return 0;  // p's own triangle: none holds p
      }
      o = o_next;
      v = next;
    }
    if (hit < 0) return 0;
    // The run of triangles whose circle holds p, from `hit` both ways.
    int lo = hit, length = 1;
    auto in_triangle = [&](int j) {
      const int j1 = j + 1 == k ? 0 : j + 1;
      ++predicates;
      return local_incircle(local_neighbour(g, s, ids[j * stride]), local_neighbour(g, s, ids[j1 * stride]), p);
    };
    for (;;) {
      const int j = lo == 0 ? k - 1 : lo - 1;
      if (length == k) return 2;  // every triangle: s itself would leave (cannot happen)
      const ex::FilterSigns in = in_triangle(j);
      if (!in.positive && !in.negative) return 2;
      if (!in.positive) break;
      lo = j;
      ++length;
    }
    for (;;) {
      const int j = lo + length >= k ? lo + length - k : lo + length;
      if (length == k) return 2;
      const ex::FilterSigns in = in_triangle(j);
      if (!in.positive && !in.negative) return 2;
      if (!in.positive) break;
      ++length;
    }
    // Triangles lo .. lo + length - 1 go: neighbours lo + 1 .. lo + length - 1 leave, and p
    // comes between neighbour lo and neighbour lo + length.
    const int size = k - length + 2;
    if (size > kLocalStar) return 2;
    for (int t = 1; t < length; ++t) virtuals -= ids[((lo + t) % k) * stride] < 0;
    if (lo + length - 1 < k) {
      // No wrap: [0 .. lo], p, [lo + length .. k).
      const int shift = 2 - length;
      if (shift > 0) {
        for (int t = k - 1; t >= lo + length; --t) ids[(t + shift) * stride] = ids[t * stride];
      } else if (shift < 0) {
        for (int t = lo + length; t < k; ++t) ids[(t + shift) * stride] = ids[t * stride];
      }
      ids[(lo + 1) * stride] = c;
      *at = lo + 1;
    } else {
      // The run wraps: [hi .. lo], then p, where hi = lo + length - k is the first kept.
      const int hi = lo + length - k;
      for (int t = hi; t <= lo; ++t) ids[(t - hi) * stride] = ids[t * stride];
      ids[(lo - hi + 1) * stride] = c;
      *at = lo - hi + 1;
    }
    k = size;
    return 1;
  };

  for (;;) {
    // Scan the target box less the visited one, a row segment at a time (cells are sorted row
    // by row, so a row of a box is one run of sites).
    for (int y = target.y0; y <= target.y1; ++y) {
      const bool rows = y >= visited.y0 && y <= visited.y1;
      for (int part = 0; part < (rows ? 2 : 1); ++part) {
        const int x0 = rows && part == 1 ? visited.x1 + 1 : target.x0;
        const int x1 = rows && part == 0 ? visited.x0 - 1 : target.x1;
        if (x0 > x1) continue;
        const int c0 = y * g.gx + x0;
        const std::uint32_t first = load_cell_start(g.cell_start, c0), last = load_cell_start(g.cell_start, c0 + (x1 - x0) + 1);
        work += 1 + (last - first);
        if (work > budget) return hand_on();
        for (std::uint32_t c = first; c < last; ++c) {
          if (static_cast<int>(c) == i) continue;
          const double2 q = load_site(g.points, static_cast<int>(c));
          if (bounded && !(q.x >= disc_box[0] && q.y >= disc_box[1] && q.x <= disc_box[2] && q.y <= disc_box[3]))
            continue;
          const ex::ApexPoint p = ex::apex_point(ex::ApexEdge{s.x, s.y, 0.0, 0.0, 0.0}, q.x, q.y);
          int at = 0;
          const int inserted = insert(static_cast<int>(c), p, &at);
          if (inserted == 2) return hand_on();
          if (inserted == 1 && bounded) {
            // The two new triangles' discs join the box (it only grows: a superset of the
            // star's discs is all the pruning needs).
            const int before = ids[(at == 0 ? k - 1 : at - 1) * stride], after = ids[(at + 1 == k ? 0 : at + 1) * stride];
            if (!grow_by_disc(s, load_site(g.points, before), q, disc_box) ||
                !grow_by_disc(s, q, load_site(g.points, after), disc_box))
              return hand_on();
          }
        }
      }
    }
    visited = target;
    CellBox need = whole;
    if (virtuals == 0) {
      // Every disc's box, with margins: the cells that must have been scanned.
      double box[4] = {HUGE_VAL, HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
      int prev = ids[(k - 1) * stride];
      double2 pv = load_site(g.points, prev);
      for (int t = 0; t < k; ++t) {
        const int id = ids[t * stride];
        const double2 pt = load_site(g.points, id);
        if (!grow_by_disc(s, pv, pt, box)) return hand_on();
        pv = pt;
      }
      for (int t = 0; t < 4; ++t) disc_box[t] = box[t];
      bounded = true;
      need = cells_of(g, box[0], box[1], box[2], box[3]);
      if (box_inside(need, visited)) break;
    } else if (box_inside(whole, visited)) {
      return hand_on();  // cannot happen off the hull
    }
    // Grow towards what is still needed, by at most half the visited box per side.
    const int rx = max((visited.x1 - visited.x0 + 1) >> 1, 1), ry = max((visited.y1 - visited.y0 + 1) >> 1, 1);
    target = {max(min(visited.x0, need.x0), visited.x0 - rx), max(min(visited.y0, need.y0), visited.y0 - ry),
              min(max(visited.x1, need.x1), visited.x1 + rx), min(max(visited.y1, need.y1), visited.y1 + ry)};
  }
  for (int t = 0; t < k; ++t) row[t] = ids[t * stride];
  w.ok = true;
  w.handed_on = false;
  w.reason = DeferReason::none;
  w.closed = true;
  w.ccw = k;
  w.cw = 0;
  w.predicates = predicates;
  w.work = work;
  return w;
}

}  // namespace expanse::detail::cuda
