#include "seam/seam_completion.hpp"

#include <algorithm>
#include <string>

#include "expanse/error.hpp"
#include "grid/apex_search.hpp"
#include "seam/edge_map.hpp"

namespace expanse::detail {
namespace {

// A front entry: the triangle on the right of the directed edge and the slot of that edge in
// it (the index of the opposite vertex), packed; no triangle yet for the seed's two edges.
constexpr std::int64_t no_triangle = -1;
std::int64_t pack(std::int32_t triangle, int slot) { return (std::int64_t{triangle} << 2) | slot; }
std::int32_t triangle_of(std::int64_t v) { return static_cast<std::int32_t>(v >> 2); }
int slot_of(std::int64_t v) { return static_cast<int>(v & 3); }

class FrontGrowth {
 public:
  FrontGrowth(const SiteSet& sites, const Hull& hull, const BucketTree& tree, PartialTriangulation& mesh)
      : hull_(hull), search_(sites, tree), mesh_(mesh), front_(1024) {}

  // Queues x->y, whose right side is `right`, unless it is a hull edge (nothing on its left).
  bool open(std::int32_t x, std::int32_t y, std::int64_t right) {
    if (hull_.is_outer_edge(x, y)) return false;
    const std::uint64_t k = EdgeMap::key(x, y);
    front_.insert(k, right);
    queue_.push_back(k);
    return true;
  }

  void seed(std::int32_t s, std::int32_t v) {
    open(s, v, no_triangle);
    open(v, s, no_triangle);
  }

  void grow() {
    auto& tris = mesh_.triangles;
    auto& nbrs = mesh_.neighbors;
    for (std::size_t head = 0; head < queue_.size(); ++head) {
      if (head >= 65536 && 2 * head >= queue_.size()) {  // drop the consumed part: keeps the queue small
        queue_.erase(queue_.begin(), queue_.begin() + static_cast<std::ptrdiff_t>(head));
        head = 0;
      }
      const std::uint64_t k = queue_[head];
      const std::int64_t* entry = front_.find(k);
      if (!entry) continue;  // closed since it was queued
      const std::int64_t right = *entry;
      front_.erase(k);
      const auto a = static_cast<std::int32_t>(k >> 32);
      const auto b = static_cast<std::int32_t>(k & 0xffffffffu);
      const std::int32_t c = search_.apex(a, b);
      if (c < 0) {
        throw Error(ErrorCode::internal, "no apex for interior edge " + std::to_string(a) + "->" +
                                             std::to_string(b) + " (please report this input)");
      }
      const auto t = static_cast<std::int32_t>(tris.size());
      tris.push_back({a, b, c});
      nbrs.push_back({no_neighbor, no_neighbor, no_neighbor});
      ++made_;
      if (right != no_triangle) {
        nbrs[t][2] = triangle_of(right);
        nbrs[triangle_of(right)][slot_of(right)] = t;
      } else if (std::int64_t* reverse = front_.find(EdgeMap::key(b, a)); reverse && *reverse == no_triangle) {
        *reverse = pack(t, 2);  // the seed's other side now knows its right triangle
      }
      attach(t, b, c, 0);
      attach(t, c, a, 1);
    }
  }

  std::size_t made() const { return made_; }
  std::uint64_t candidates_tested() const { return search_.candidates_tested(); }

 private:
  // Edge x->y of the new triangle t (t lies on its left; `slot` is its index in t). If x->y is
  // waiting in the front, t is the triangle it was waiting for; otherwise y->x opens.
  void attach(std::int32_t t, std::int32_t x, std::int32_t y, int slot) {
    const std::uint64_t k = EdgeMap::key(x, y);
    if (std::int64_t* waiting = front_.find(k)) {
      const std::int64_t right = *waiting;
      if (right != no_triangle) {
        mesh_.neighbors[t][slot] = triangle_of(right);
        mesh_.neighbors[triangle_of(right)][slot_of(right)] = t;
      }
      front_.erase(k);
      return;
    }
    open(y, x, pack(t, slot));
  }

  const Hull& hull_;
  ApexSearch search_;
  PartialTriangulation& mesh_;
  EdgeMap front_;
  std::vector<std::uint64_t> queue_;
  std::size_t made_ = 0;
};

}  // namespace

std::vector<std::array<std::int32_t, 3>> derive_neighbors(const std::vector<Triangle>& triangles) {
  // Each directed edge x->y is filed under x (compressed rows, no hashing: a device can hand over
  // millions of triangles); its twin y->x is then among the few edges filed under y.
  std::vector<std::array<std::int32_t, 3>> neighbors(triangles.size(), {no_neighbor, no_neighbor, no_neighbor});
  std::int32_t vertices = 0;
  for (const Triangle& t : triangles) vertices = std::max({vertices, t[0] + 1, t[1] + 1, t[2] + 1});
  std::vector<std::int32_t> start(static_cast<std::size_t>(vertices) + 1, 0);
  for (const Triangle& t : triangles) {
    for (std::int32_t v : t) ++start[v + 1];
  }
  for (std::size_t v = 0; v < static_cast<std::size_t>(vertices); ++v) start[v + 1] += start[v];
  std::vector<std::int32_t> fill(start.begin(), start.end() - 1);
  std::vector<std::int32_t> edges(3 * triangles.size());  // triangle * 3 + slot of the edge
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k) edges[fill[triangles[t][(k + 1) % 3]]++] = static_cast<std::int32_t>(3 * t + k);
  }
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const std::int32_t x = triangles[t][(k + 1) % 3], y = triangles[t][(k + 2) % 3];
      for (std::int32_t e = start[y]; e < start[y + 1]; ++e) {
        const std::int32_t u = edges[e] / 3, j = edges[e] % 3;
        if (triangles[u][(j + 2) % 3] == x) {
          neighbors[t][k] = u;
          break;
        }
      }
    }
  }
  return neighbors;
}

SeamStats complete_seam(const SiteSet& sites, const Hull& hull, const BucketTree& tree,
                        PartialTriangulation& mesh) {
  if (mesh.neighbors.size() != mesh.triangles.size()) mesh.neighbors = derive_neighbors(mesh.triangles);
  const std::size_t expected = 2 * static_cast<std::size_t>(sites.size()) - hull.sites.size() - 2;
  mesh.triangles.reserve(expected);
  mesh.neighbors.reserve(expected);

  FrontGrowth growth(sites, hull, tree, mesh);
  SeamStats stats;
  if (mesh.triangles.empty()) {
    // The paper's sequential algorithm: seed near the centre, first edge to its nearest
    // neighbour (always a Delaunay edge).
    ApexSearch search(sites, tree);
    const Box& box = sites.bounds;
    const std::int32_t s = search.nearest_site({0.5 * box.min_x + 0.5 * box.max_x, 0.5 * box.min_y + 0.5 * box.max_y});
    growth.seed(s, search.nearest_neighbor(s));
    stats.open_edges = 2;
  } else {
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
      for (int k = 0; k < 3; ++k) {
        if (mesh.neighbors[t][k] != no_neighbor) continue;
        const std::int32_t x = mesh.triangles[t][(k + 1) % 3], y = mesh.triangles[t][(k + 2) % 3];
        if (growth.open(y, x, pack(static_cast<std::int32_t>(t), k))) ++stats.open_edges;
      }
    }
  }
  growth.grow();
  stats.triangles_made = growth.made();
  stats.candidates_tested = growth.candidates_tested();
  if (mesh.triangles.size() != expected) {
    throw Error(ErrorCode::internal, "seam completion made " + std::to_string(mesh.triangles.size()) +
                                         " triangles, expected 2n - h - 2 = " + std::to_string(expected));
  }
  return stats;
}

}  // namespace expanse::detail
