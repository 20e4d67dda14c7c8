#include "seam/adjacency_audit.hpp"

#include <cstdint>
#include <vector>

#include "seam/edge_map.hpp"

namespace expanse::detail {
namespace {

std::uint64_t mix(std::uint32_t v) {
  std::uint64_t x = v + 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

}  // namespace

bool adjacency_is_trustworthy(const PartialTriangulation& partial, const Hull& hull) {
  const auto& tris = partial.triangles;
  const auto& nbrs = partial.neighbors;
  if (nbrs.size() != tris.size()) return false;

  // 1. Symmetric links.
  for (std::size_t t = 0; t < tris.size(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const std::int32_t u = nbrs[t][k];
      if (u == no_neighbor) continue;
      if (u < 0 || static_cast<std::size_t>(u) >= tris.size()) return false;
      const auto& back = nbrs[u];
      const auto self = static_cast<std::int32_t>(t);
      if (back[0] != self && back[1] != self && back[2] != self) return false;
    }
  }

  // 2. Which sites have an open fan? Around a site, each neighbour of a closed fan is met twice
  // (once after, once before the site), so the XOR of hashed neighbours is 0; a hull site's
  // complete fan leaves its two hull neighbours. A mismatch marks the fan open (a hash can only
  // err towards "closed", and that costs a hole the seam stage's final count catches).
  const std::size_t n = hull.predecessor.size();
  std::vector<std::uint64_t> fan(n, 0);
  for (const Triangle& t : tris) {
    for (int k = 0; k < 3; ++k) fan[t[k]] ^= mix(static_cast<std::uint32_t>(t[(k + 1) % 3])) ^ mix(static_cast<std::uint32_t>(t[(k + 2) % 3]));
  }
  std::vector<std::int32_t> successor(n, -1);
  for (std::size_t i = 0; i < hull.sites.size(); ++i) successor[hull.sites[i]] = hull.sites[(i + 1) % hull.sites.size()];
  std::vector<bool> open_fan(n);
  for (std::size_t v = 0; v < n; ++v) {
    const std::uint64_t closed = hull.predecessor[v] < 0 ? 0
                                 : mix(static_cast<std::uint32_t>(hull.predecessor[v])) ^ mix(static_cast<std::uint32_t>(successor[v]));
    open_fan[v] = fan[v] != closed;
  }

  // 3. An edge marked open must be a hull edge or join two open fans, and no triangle may lie
  // across it: look among the triangles touching open fans (the seam's neighbourhood).
  EdgeMap seam_edges(1024);
  for (std::size_t t = 0; t < tris.size(); ++t) {
    const Triangle& tri = tris[t];
    if (!open_fan[tri[0]] && !open_fan[tri[1]] && !open_fan[tri[2]]) continue;
    for (int k = 0; k < 3; ++k) seam_edges.insert(EdgeMap::key(tri[(k + 1) % 3], tri[(k + 2) % 3]), 1);
  }
  for (std::size_t t = 0; t < tris.size(); ++t) {
    for (int k = 0; k < 3; ++k) {
      if (nbrs[t][k] != no_neighbor) continue;
      const std::int32_t x = tris[t][(k + 1) % 3], y = tris[t][(k + 2) % 3];
      if (hull.is_outer_edge(y, x)) continue;  // x->y is a hull edge walked counter-clockwise
      if (!open_fan[x] || !open_fan[y]) return false;
      if (seam_edges.find(EdgeMap::key(y, x))) return false;
    }
  }
  return true;
}

}  // namespace expanse::detail
