#pragma once
// One site's star, walked as the per-site kernel does it: the nearest site first, then apex
// after apex counter-clockwise until the star closes or meets the hull, then clockwise from the
// nearest site. Shared by star_kernel (one thread per site) and by the host tests and work
// counts that run the same code on the CPU (device_compat.cuh).
#include "star_common.cuh"

namespace expanse::detail::cuda {

/// Why a site's star deferred to the seam stage.
enum class DeferReason : unsigned char {
  none,
  undecided,  ///< a predicate the device filters could not decide, or the work budget ran out
  full_row,   ///< more than kStar neighbours
  no_apex,    ///< a search found nothing (cannot happen for an edge that is not a hull edge)
};

struct StarWalk {
  bool ok = false;       ///< false: the site defers (see reason)
  DeferReason reason = DeferReason::undecided;
  bool closed = false;   ///< the star goes all the way round
  int ccw = 0;           ///< neighbours stored from the row's start, counter-clockwise
  int cw = 0;            ///< neighbours stored from the row's end, clockwise from the first
  unsigned predicates = 0;
  unsigned work = 0;     ///< cells + sites visited
  bool handed_on = false;  ///< a first-pass walk stopped at a candidate only the exact path decides
};

/// Walks the star of sorted site i into row[0 .. kStar): the counter-clockwise part from index 0
/// up, the clockwise part from the end down, so the row read from index kStar - cw on, wrapping,
/// is the whole star counter-clockwise. pred[v] is v's hull predecessor (or -1).
EXPANSE_DEVICE StarWalk walk_star(const GridView& g, const int* pred, int i, int* row, unsigned budget) {
  StarWalk w;
  const double2 s = g.points[i];
  bool ok = true;
  const int v0 = nearest_site(g, i, s, &ok, &w.work, budget);
  if (!ok) return w;
  if (v0 < 0) {
    w.reason = DeferReason::no_apex;
    return w;
  }
  // Counter-clockwise: (s, v, apex(s->v)) until the star closes or s->v is an outer edge; then,
  // if it met the hull, clockwise from v0: (v, s, apex(v->s)). One loop and one find_apex call
  // for both directions, so the search is inlined once.
  row[0] = v0;
  w.ccw = 1;
  bool clockwise = false;
  int v = v0;
  for (;;) {
    if (!clockwise && pred[i] == v) {
      clockwise = true;  // s->v is an outer edge: the rest lies clockwise from v0
      v = v0;
    }
    if (clockwise && pred[v] == i) break;  // v->s is an outer edge: the star is complete
    const int from = clockwise ? v : i, to = clockwise ? i : v;
    int status;
    const int c = find_apex(g, from, g.points[from], to, g.points[to], &status, &w.predicates, &w.work, budget);
    if (status != apex_found) {
      if (status == apex_none) w.reason = DeferReason::no_apex;
      return w;
    }
    if (c == v0) {
      if (clockwise) {
        w.reason = DeferReason::no_apex;  // a clockwise walk cannot close the star
        return w;
      }
      w.closed = true;
      break;
    }
    if (w.ccw + w.cw >= kStar) {
      w.reason = DeferReason::full_row;
      return w;
    }
    if (clockwise)
      row[kStar - 1 - w.cw++] = c;
    else
      row[w.ccw++] = c;
    v = c;
  }
  w.ok = true;
  w.reason = DeferReason::none;
  return w;
}

/// An odd site's inbox read once (StarInbox), its posts then looked up in registers: the
/// words are loaded together, not one post after another as each step needs them (the recording
/// kernel 1.60 -> 1.43 ms at 4096^2 uniform on an H200; the rest of its time is traffic). Words past the posts are never read (they are not written either).
struct InboxPosts {
  int b[kInboxTriples], u[kInboxTriples], a[kInboxTriples];
  int count;

  EXPANSE_DEVICE_FORCE InboxPosts(const StarInbox& inbox, int i) : count(inbox.posted(i)) {
    const int* r = inbox.row(i);
#if defined(__CUDACC__)
#pragma unroll
#endif
    for (int k = 0; k < kInboxTriples; ++k) {
      const bool here = k < count;
      b[k] = here ? r[3 * k] : -1;
      u[k] = here ? r[3 * k + 1] : -1;
      a[k] = here ? r[3 * k + 2] : -1;
    }
  }

  /// As StarInbox::apex: the first post that names the step wins (unused slots hold -1, which
  /// names nothing). *then: the step after that one where the same post names it too (a post
  /// (b, u, a) found at b gives u and then a), else -1.
  EXPANSE_DEVICE_FORCE int apex(int v, bool counter_clockwise, int* then) const {
    int found = -1, next = -1;
#if defined(__CUDACC__)
#pragma unroll
#endif
    for (int k = kInboxTriples - 1; k >= 0; --k) {
      const int before = counter_clockwise ? b[k] : a[k], after = counter_clockwise ? a[k] : b[k];
      if (u[k] == v && after >= 0) {
        found = after;
        next = -1;
      } else if (before == v) {
        found = u[k];
        next = after;
      }
    }
    *then = next;
    return found;
  }
};

/// Odd site i's star taken from its inbox alone (StarInbox), as walk_star_boxes' reading walk
/// takes it: the posted first neighbour, then step after step, counter-clockwise and, past an
/// outer edge, clockwise, into row[] and *w laid out as that walk lays them. False at the first
/// step the inbox does not hold (or anything the full walk would defer at): the site then needs
/// the full walk, which makes the same steps before its first search. Both agree on every star
/// the inbox holds whole (tests/unit/test_cuda_star_walk.cpp compares them on the CPU).
///
/// *owned: the star's triangles that i owns (owned_triangles), counted step by step, each step's
/// triangle being (i, v, c) in some order, so that the row is not read back. With row null
/// nothing is written: the recording kernel walks once to learn whether the inbox holds the
/// whole star, and writes the row only then (the sites that must search have their rows written
/// by the full walk).
EXPANSE_DEVICE bool walk_from_inbox(const int* pred, int i, int* row, const StarInbox& inbox, StarWalk* w,
                                    int* owned) {
  const InboxPosts posts(inbox, i);
  if (posts.count == 0) return false;
  const int v0 = posts.u[0];  // StarInbox::first_neighbour
  const int pred_s = pred[i];
  int ccw = 1, cw = 0;
  bool clockwise = false, closed = false;
  unsigned steps = 0;
  int mine = 0;
  int v = v0;
  int then = -1;  // the step after v, where the last look-up's post named it
  if (row) row[0] = v0;
  for (;;) {
    if (!clockwise && pred_s == v) {
      clockwise = true;  // s->v is an outer edge: the rest lies clockwise from v0
      v = v0;
      then = -1;
    }
    if (clockwise && pred[v] == i) break;  // v->s is an outer edge: the star is complete
    int c = then;
    if (c < 0) c = posts.apex(v, !clockwise, &then);
    else then = -1;
    if (c < 0) return false;
    ++steps;
    mine += i < v && i < c;
    if (c == v0) {
      if (clockwise) return false;  // the full walk defers here (no apex)
      closed = true;
      break;
    }
    if (ccw + cw >= kStar) return false;  // the full walk defers here (full row)
    const int at = clockwise ? kStar - 1 - cw++ : ccw++;
    if (row) row[at] = c;
    v = c;
  }
  w->ok = true;
  w->reason = DeferReason::none;
  w->closed = closed;
  w->ccw = ccw;
  w->cw = cw;
  w->predicates = 0;
  w->work = steps;
  w->handed_on = false;
  *owned = mine;
  return true;
}

/// The packed per-site info of a finished walk (star_common.cuh).
EXPANSE_DEVICE_FORCE std::uint32_t star_info(const StarWalk& w) {
  return static_cast<std::uint32_t>(w.ccw + w.cw) | (static_cast<std::uint32_t>((kStar - w.cw) & (kStar - 1)) << 8) |
         (w.closed ? kClosedBit : 0u);
}

/// Triangles of site i's star that i owns (it is their smallest vertex).
EXPANSE_DEVICE int owned_triangles(const int* star, std::uint32_t info, int i) {
  const int deg = star_degree(info);
  const int tris = star_closed(info) ? deg : deg - 1;
  int count = 0;
  for (int t = 0; t < tris; ++t) {
    const int a = star_at(star, info, i, t), b = star_at(star, info, i, t + 1);
    count += (i < a && i < b);
  }
  return count;
}

}  // namespace expanse::detail::cuda
