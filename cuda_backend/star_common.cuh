#pragma once
// Bucketing and star bookkeeping shared by both layouts.
#include <cstdint>

#include "device_geometry.cuh"

namespace expanse::detail::cuda {

/// Stars hold at most this many neighbours (a power of two); a site with more defers (the seam
/// stage makes its triangles). 16 was too few: sites on the flat hull sides of uniform inputs
/// fan out to many hull-hugging neighbours, and 14 of 10^6 uniform sites deferred, each deferral
/// sending the whole pipeline through the seam stage (counted with bench/src/star_work.cpp).
inline constexpr int kStar = 32;
inline constexpr std::uint32_t kClosedBit = 1u << 16;
inline constexpr std::uint32_t kDeferredBit = 1u << 17;

EXPANSE_DEVICE_FORCE int star_degree(std::uint32_t info) { return static_cast<int>(info & 255u); }
EXPANSE_DEVICE_FORCE int star_start(std::uint32_t info) { return static_cast<int>((info >> 8) & 255u); }
EXPANSE_DEVICE_FORCE bool star_closed(std::uint32_t info) { return (info & kClosedBit) != 0; }
EXPANSE_DEVICE_FORCE bool star_deferred(std::uint32_t info) { return (info & kDeferredBit) != 0; }

/// t-th neighbour of site o in CCW order, t in [-1, deg + 1] (wrapping, for closed stars). The
/// wrap by comparisons, not `%`: an integer remainder is ~20 instructions on the GPU, and the
/// emit kernel wraps twice for every entry of every star it searches.
EXPANSE_DEVICE_FORCE int star_at(const int* star, std::uint32_t info, int o, int t) {
  const int deg = star_degree(info);
  t = t < 0 ? t + deg : t;
  t = t >= deg ? t - deg : t;
  t = t >= deg ? t - deg : t;  // deg 1, t = 2
  return star[static_cast<std::size_t>(o) * kStar + ((star_start(info) + t) & (kStar - 1))];
}

EXPANSE_DEVICE_FORCE int star_find(const int* star, std::uint32_t info, int o, int u) {
  const int deg = star_degree(info);
  for (int t = 0; t < deg; ++t)
    if (star_at(star, info, o, t) == u) return t;
  return -1;
}

/// The block that launch slot `b` of `blocks` runs when blocks start from both ends of the order
/// inwards: 0, blocks - 1, 1, blocks - 2, ... (a permutation: every block runs once). On quantile
/// cells the first and last rows of the cell order hold the far tails in y, whose walks are the
/// longest; launched last, they made the phase's tail (grow_per_site).
EXPANSE_DEVICE_FORCE int ends_first_block(int b, int blocks) { return (b & 1) ? blocks - 1 - (b >> 1) : b >> 1; }

/// Two phases of walks: the sites of even local id first, then the odd ones (a cell's sites fall
/// in both). A finished walk of the first phase posts, to each odd neighbour w, the two
/// triangles it shares with w, as the triple (b, u, a): around w, counter-clockwise, b comes just
/// before u and a just after (-1 where u's star is open there). An odd site's walk then starts
/// at a posted neighbour (no nearest-neighbour search) and takes a step from its inbox wherever
/// the triangle it seeks has an even vertex besides itself, searching only for the triangles
/// whose three vertices are all odd: about one in four, where without the posts every triangle
/// is searched for three times, once from each vertex. Both ways give the same star: the posts
/// come from exact stars, and a Delaunay triangle is one triangle whoever finds it.
///
/// Room for 5 posts in a 64-byte row; more are dropped, and their steps searched for. Two
/// phases, not more: a later phase's warps wait for their few searching lanes, and every phase
/// adds its recording kernel and its tail (docs/benchmarks.md, "tried and not kept").
inline constexpr int kInboxTriples = 5;
inline constexpr int kInboxWords = 16;  // 5 triples, padded to 64 bytes

struct StarInbox {
  int* slots = nullptr;             ///< kInboxWords per odd site (local id i: row i / 2); null: none
  std::uint32_t* counts = nullptr;  ///< triples posted to each odd site (past kInboxTriples dropped)
  bool reading = false;             ///< the second phase: walks read their inbox, nobody posts

  EXPANSE_DEVICE_FORCE static bool odd(int v) { return (v & 1) != 0; }
  EXPANSE_DEVICE_FORCE bool posting() const { return slots && !reading; }
  EXPANSE_DEVICE_FORCE int posted(int i) const {
    const int c = static_cast<int>(counts[i >> 1]);
    return c < kInboxTriples ? c : kInboxTriples;
  }
  EXPANSE_DEVICE_FORCE const int* row(int i) const { return slots + static_cast<std::size_t>(i >> 1) * kInboxWords; }

  /// A neighbour of odd site i from its inbox, or -1.
  EXPANSE_DEVICE_FORCE int first_neighbour(int i) const { return posted(i) == 0 ? -1 : row(i)[1]; }
  /// The apex of i->v (counter_clockwise: the neighbour just after v around i) or of v->i (the
  /// one just before), from odd site i's inbox, or -1. InboxPosts::apex (star_walk.cuh) applies
  /// the same rule to posts held in registers, for the second phase's recording kernel; the full
  /// walk reads the row here, a post at a time, since 15 more live registers would cost its scan
  /// loop more. The CPU test compares the two walks' stars.
  EXPANSE_DEVICE_FORCE int apex(int i, int v, bool counter_clockwise) const {
    const int* r = row(i);
    const int count = posted(i);
    for (int k = 0; k < count; ++k) {
      const int b = r[3 * k], u = r[3 * k + 1], a = r[3 * k + 2];
      if (counter_clockwise) {
        if (u == v && a >= 0) return a;
        if (b == v) return u;
      } else {
        if (u == v && b >= 0) return b;
        if (a == v) return u;
      }
    }
    return -1;
  }
};

/// Posts even site u's finished star (the row and info of star_common.cuh) to its odd
/// neighbours' inboxes. `bump` returns a counter's old value and adds one (an atomic on the
/// device).
template <typename Bump>
EXPANSE_DEVICE_FORCE void post_star(const StarInbox& inbox, const int* star, std::uint32_t info, int u, Bump bump) {
  const int deg = star_degree(info);
  const bool closed = star_closed(info);
  for (int t = 0; t < deg; ++t) {
    const int w = star_at(star, info, u, t);
    if (!StarInbox::odd(w)) continue;
    const unsigned k = bump(inbox.counts + (w >> 1));
    if (k >= static_cast<unsigned>(kInboxTriples)) continue;
    // The triangles (u, star t-1, w) and (u, w, star t+1): around w, u comes just after star
    // t+1 and just before star t-1.
    int* r = inbox.slots + static_cast<std::size_t>(w >> 1) * kInboxWords + 3 * k;
    r[0] = t + 1 < deg || closed ? star_at(star, info, u, t + 1) : -1;
    r[1] = u;
    r[2] = t > 0 || closed ? star_at(star, info, u, t - 1) : -1;
  }
}

}  // namespace expanse::detail::cuda
