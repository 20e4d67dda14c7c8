#include "backends/vulkan/host_links.hpp"

#include <atomic>
#include <bit>
#include <unordered_map>
#if defined(__SSE2__)
#include <emmintrin.h>  // HostStar::find
#endif

#include "backends/vulkan/host_threads.hpp"
#include "expanse/error.hpp"
#include "host_device.h"

namespace expanse::detail::vk {
namespace {

static_assert(shared::STAR_ROW == 16, "HostStar::find compares a row as four vectors of four");

// A star as the host reads it, in place (host_device.h's info word, STAR_ROW ints a row).
struct HostStar {
  const std::int32_t* row = nullptr;
  std::int32_t site = -1;
  std::uint32_t info = 0;
  std::int32_t base = -1;
  int degree = 0, start = 0;
  bool closed() const { return shared::star_closed(info); }
  bool deferred() const { return shared::star_deferred(info); }
  bool emitted() const { return !deferred() && base >= 0; }  // owns output triangles
  int triangles() const { return shared::star_triangles(info); }
  std::uint32_t owned() const { return shared::star_owned(info); }
  bool owns(int t) const { return ((owned() >> t) & 1u) != 0; }
  std::int32_t output(int t) const {
    std::uint32_t below = owned() & ((1u << t) - 1u);
    below = below - ((below >> 1) & 0x5555u);  // 16-bit popcount without a library call
    below = (below & 0x3333u) + ((below >> 2) & 0x3333u);
    below = (below + (below >> 4)) & 0x0f0fu;
    return base + std::int32_t((below + (below >> 8)) & 0x1fu);
  }
  std::int32_t at(int t) const {
    t = t < 0 ? t + degree : (t >= degree ? t - degree : t);
    return row[(start + t) & 15];
  }
  // u's position in the star, or -1. The row's 16 slots compared at once, then
  // only the star's slots kept (degree of them from `start`, wrapping); a site is in a star
  // at most once. 1M uniform sites on lavapipe: links 68 -> 55-57 ms against a loop over the
  // star's entries.
  int find(std::int32_t u) const {
    std::uint32_t matches = 0;
#if defined(__SSE2__)
    // GCC leaves the loop below scalar (a compare and a set per slot): lavapipe, 1M uniform,
    // links 56-58 ms with it, 46.0-46.2 with these four compares (2026-11-25).
    const __m128i key = _mm_set1_epi32(u);
    for (int q = 0; q < 4; ++q) {
      const __m128i slots = _mm_loadu_si128(reinterpret_cast<const __m128i*>(row) + q);
      matches |= std::uint32_t(_mm_movemask_ps(_mm_castsi128_ps(_mm_cmpeq_epi32(slots, key)))) << (4 * q);
    }
#else
    for (int k = 0; k < 16; ++k) matches |= std::uint32_t(row[k] == u) << k;
#endif
    const std::uint32_t span = degree >= 16 ? 0xffffu : (1u << degree) - 1u;
    matches &= ((span << start) | (span >> (16 - start))) & 0xffffu;
    if (matches == 0) return -1;
    return (std::countr_zero(matches) - start) & 15;
  }
};

}  // namespace

// A first pass checks every star (ids in range, degree, output range); the second reads them
// unchecked.
void link_stars(const std::int32_t* star, const std::int32_t* info_base, std::size_t n,
                PartialTriangulation& partial) {
  const std::size_t count = partial.triangles.size();
  auto& nbrs = partial.neighbors;
  nbrs.assign(count, {no_neighbor, no_neighbor, no_neighbor});
  auto star_of = [&](std::int32_t s) {
    HostStar h;
    h.site = s;
    h.row = star + 16 * std::size_t(s);
    h.info = std::uint32_t(info_base[2 * std::size_t(s)]);
    h.base = info_base[2 * std::size_t(s) + 1];
    h.degree = int(h.info & 31u);
    h.start = int((h.info >> 5) & 15u);
    return h;
  };
  const unsigned workers = host_workers(n);
  std::atomic<bool> bad{false};
  parallel_chunks(n, workers, [&](std::size_t begin, std::size_t end, unsigned) {
    for (std::size_t s = begin; s < end; ++s) {
      const HostStar h = star_of(std::int32_t(s));
      if (h.deferred()) continue;
      bool ok = h.degree >= 1 && h.degree <= 16 &&
                (h.base < 0 || std::size_t(h.output(16)) <= count);
      for (int t = 0; t < h.degree; ++t) ok = ok && h.at(t) >= 0 && std::size_t(h.at(t)) < n;
      if (!ok) bad = true;
    }
  });
  if (bad) throw Error(ErrorCode::internal, "Vulkan: the device returned an invalid star");
  // Output index of triangle (o, u, w) in the star of its owner o, or no_neighbor.
  auto index_in = [&](const HostStar& o, std::int32_t u, std::int32_t w) -> std::int32_t {
    if (!o.emitted()) return no_neighbor;
    const int t = o.find(u);
    if (t < 0 || t >= o.triangles() || o.at(t + 1) != w || !o.owns(t)) return no_neighbor;
    return o.output(t);
  };
  // Output index of the counter-clockwise triangle (x, y, z); `own` is a star already read.
  auto index = [&](const HostStar& own, std::int32_t x, std::int32_t y, std::int32_t z) {
    std::int32_t o = x, u = y, w = z;
    if (y < o && y < z) {
      o = y, u = z, w = x;
    } else if (z < o && z < y) {
      o = z, u = x, w = y;
    }
    return index_in(o == own.site ? own : star_of(o), u, w);
  };
  // The same, for the triangle at position k of a star already read whose site owns it (the
  // find that index() would make is the one this position came from): lavapipe, 1M uniform,
  // links 46 -> 41.5 ms.
  auto owned_at = [](const HostStar& o, int k) -> std::int32_t {
    k = k < 0 ? k + o.degree : (k >= o.degree ? k - o.degree : k);
    return o.emitted() && o.owns(k) ? o.output(k) : no_neighbor;
  };
  std::vector<std::vector<std::int32_t>> open(workers);
  parallel_chunks(n, workers, [&](std::size_t begin, std::size_t end, unsigned w) {
    for (std::size_t si = begin; si < end; ++si) {
      const HostStar me = star_of(std::int32_t(si));
      if (!me.emitted()) continue;
      const std::int32_t s = me.site;
      for (std::uint32_t left = me.owned(); left != 0; left &= left - 1) {
        const int t = std::countr_zero(left);
        if (t >= me.triangles()) break;  // never, for a valid star
        const std::int32_t a = me.at(t), b = me.at(t + 1);
        const std::int32_t out = me.output(t);
        auto& row = nbrs[std::size_t(out)];
        // Opposite s: (b, a, r), r the neighbour of a before b (or of b after a).
        const HostStar sa = star_of(a), sb = star_of(b);
        if (!sa.deferred()) {
          const int p = sa.find(b);
          if (p >= 0 && (p > 0 || sa.closed())) {
            const std::int32_t r = sa.at(p - 1);
            row[0] = a < b && a < r ? owned_at(sa, p - 1) : index(sa, b, a, r);
          }
        } else if (!sb.deferred()) {
          const int q = sb.find(a);
          if (q >= 0 && (q < sb.degree - 1 || sb.closed())) row[0] = index(sb, b, a, sb.at(q + 1));
        } else {
          open[w].push_back(3 * out);
        }
        // Opposite a: (s, b, next), s's next triangle; opposite b: (s, previous, a).
        if (me.closed() || t + 2 < me.degree) {
          const std::int32_t next = me.at(t + 2);
          row[1] = s < next ? owned_at(me, t + 1) : index(me, s, b, next);  // s < b: s owns t
        }
        if (me.closed() || t >= 1) {
          const std::int32_t previous = me.at(t - 1);
          row[2] = s < previous ? owned_at(me, t - 1) : index(me, s, previous, a);  // s < a
        }
      }
    }
  });
  std::vector<std::int32_t> slots;
  for (const auto& list : open) slots.insert(slots.end(), list.begin(), list.end());
  pair_unresolved(slots, partial);
}

void pair_unresolved(const std::vector<std::int32_t>& slots, PartialTriangulation& partial) {
  if (slots.empty()) return;
  const std::size_t count = partial.triangles.size();
  auto& nbrs = partial.neighbors;
  auto edge = [&](std::int32_t slot, bool reversed) {
    const Triangle& t = partial.triangles[std::size_t(slot / 3)];
    const int k = slot % 3;
    std::uint64_t x = std::uint32_t(t[std::size_t((k + 1) % 3)]);
    std::uint64_t y = std::uint32_t(t[std::size_t((k + 2) % 3)]);
    if (reversed) std::swap(x, y);
    return (x << 32) | y;
  };
  std::unordered_map<std::uint64_t, std::int32_t> open;
  open.reserve(slots.size());
  for (std::int32_t slot : slots) {
    if (slot < 0 || std::size_t(slot / 3) >= count)
      throw Error(ErrorCode::internal, "Vulkan: the device listed an invalid adjacency slot");
    open.emplace(edge(slot, false), slot);
  }
  for (std::int32_t slot : slots) {
    const auto found = open.find(edge(slot, true));
    nbrs[std::size_t(slot / 3)][std::size_t(slot % 3)] =
        found == open.end() ? no_neighbor : found->second / 3;
  }
}

bool open_edges_check_out(const std::vector<std::int32_t>& open_slots,
                          const std::vector<std::int32_t>& paired_slots,
                          const PartialTriangulation& partial) {
  const std::size_t count = partial.triangles.size();
  auto edge_at = [&](std::int32_t slot, std::int32_t& x, std::int32_t& y) {
    const Triangle& t = partial.triangles[std::size_t(slot / 3)];
    x = t[std::size_t((slot % 3 + 1) % 3)];
    y = t[std::size_t((slot % 3 + 2) % 3)];
  };
  auto key = [](std::int32_t x, std::int32_t y) {
    return (std::uint64_t(std::uint32_t(x)) << 32) | std::uint32_t(y);
  };
  std::unordered_map<std::uint64_t, int> still_open;
  for (const auto* list : {&open_slots, &paired_slots}) {
    for (std::int32_t slot : *list) {
      if (slot < 0 || std::size_t(slot / 3) >= count) return false;
      const std::int32_t u = partial.neighbors[std::size_t(slot / 3)][std::size_t(slot % 3)];
      std::int32_t x, y;
      edge_at(slot, x, y);
      if (u == no_neighbor) {
        still_open.emplace(key(x, y), 0);
        continue;
      }
      if (u < 0 || std::size_t(u) >= count) return false;
      const Triangle& other = partial.triangles[std::size_t(u)];
      int j = 0;
      while (j < 3 && !(other[std::size_t((j + 1) % 3)] == y && other[std::size_t((j + 2) % 3)] == x)) ++j;
      if (j == 3 || partial.neighbors[std::size_t(u)][std::size_t(j)] != slot / 3) return false;
    }
  }
  for (const auto& [edge, unused] : still_open)
    if (still_open.count((edge << 32) | (edge >> 32))) return false;
  return true;
}

}  // namespace expanse::detail::vk
