#include "seam/seam_completion.hpp"

#include <algorithm>
#include <string>

#include "expanse/error.hpp"
#include "grid/apex_search.hpp"
#include "input/parallel.hpp"
#include "seam/edge_map.hpp"
#include "support/timing.hpp"

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
      const std::int32_t c = search_.apex_search(a, b);
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

// derive_neighbors' last step for one block of vertices [first_vertex, first_vertex + span):
// its m corners (triangle * 3 + slot, in no useful order) filed by vertex, then around each
// vertex v the edge v->w of one triangle paired with the edge w->v of another, once, at the
// smaller vertex. Writes only links of this block's pairs.
void match_block_corners(const std::vector<Triangle>& triangles, const std::int32_t* corners, std::size_t m,
                         std::size_t first_vertex, std::size_t span, std::vector<TriangleNeighbors>& neighbors) {
  // Per corner filed by vertex: the vertex after it (its edge leaves v towards it) and the
  // vertex before it (its edge comes from there), with the corner. Each triangle is read once.
  struct Corner {
    std::int32_t next, previous, corner;
  };
  thread_local std::vector<std::uint32_t> start;
  thread_local std::vector<Corner> read, filed;
  thread_local std::vector<std::uint32_t> vertex_of;
  start.assign(span + 1, 0);
  for (auto* v : {&read, &filed}) v->resize(std::max(v->size(), m));
  vertex_of.resize(std::max(vertex_of.size(), m));
  for (std::size_t i = 0; i < m; ++i) {
    const std::int32_t c = corners[i];
    const Triangle& tri = triangles[c / 3];
    const int k = c % 3;
    const auto v = static_cast<std::uint32_t>(static_cast<std::size_t>(tri[k]) - first_vertex);
    vertex_of[i] = v;
    read[i] = {tri[(k + 1) % 3], tri[(k + 2) % 3], c};
    ++start[v + 1];
  }
  for (std::size_t v = 0; v < span; ++v) start[v + 1] += start[v];
  for (std::size_t i = 0; i < m; ++i) filed[start[vertex_of[i]]++] = read[i];
  // start[v] is now where v's corners end; they begin at start[v - 1].
  for (std::size_t v = 0; v < span; ++v) {
    const std::int32_t self = static_cast<std::int32_t>(first_vertex + v);
    const std::uint32_t begin = v == 0 ? 0 : start[v - 1], end = start[v];
    for (std::uint32_t a = begin; a < end; ++a) {
      const std::int32_t w = filed[a].next;  // triangle t holds self->w opposite slot k + 2
      if (w < self) continue;                // matched at w
      for (std::uint32_t z = begin; z < end; ++z) {
        if (filed[z].previous != w) continue;  // triangle u holds w->self opposite slot j + 1
        const std::int32_t t = filed[a].corner / 3, k = filed[a].corner % 3;
        const std::int32_t u = filed[z].corner / 3, j = filed[z].corner % 3;
        neighbors[t][(k + 2) % 3] = u;
        neighbors[u][(j + 1) % 3] = t;
        break;
      }
    }
  }
}

// The open links of `mesh` (no_neighbor inside the hull: the hull's own edges are skipped by
// FrontGrowth::open) as front entries, in triangle order, found on all threads.
std::vector<std::vector<std::int64_t>> find_open_links(const PartialTriangulation& mesh) {
  const std::size_t count = mesh.triangles.size();
  const std::size_t chunks = chunk_count(count);
  std::vector<std::vector<std::int64_t>> open(chunks);
  // A few hundred open edges among tens of millions of links: blocks of triangles are first
  // tested as a whole (links are >= 0 and no_neighbor is -1, so a block holds one exactly when
  // the OR of its links is negative; the OR vectorises), then searched.
  static_assert(no_neighbor < 0);
  parallel_chunks(count, chunks, [&](std::size_t chunk, std::size_t begin, std::size_t end) {
    constexpr std::size_t block = 64;
    for (std::size_t lo = begin; lo < end; lo += block) {
      const std::size_t hi = std::min(end, lo + block);
      const std::int32_t* links = mesh.neighbors[lo].data();
      std::int32_t any = 0;
      for (std::size_t j = 0; j < 3 * (hi - lo); ++j) any |= links[j];
      if (any >= 0) continue;
      for (std::size_t t = lo; t < hi; ++t) {
        for (int k = 0; k < 3; ++k) {
          if (mesh.neighbors[t][k] == no_neighbor) open[chunk].push_back(pack(static_cast<std::int32_t>(t), k));
        }
      }
    }
  });
  return open;
}

// Queues the front `mesh` leaves open in `growth` and returns how many edges it queued: one
// seed near the centre when `mesh` is empty, else the open links (as the backend listed them,
// or found here).
std::size_t queue_front(const SiteSet& sites, const BucketTree& tree, const PartialTriangulation& mesh,
                        FrontGrowth& growth) {
  if (mesh.triangles.empty()) {
    // The paper's sequential algorithm: seed near the centre, first edge to its nearest site
    // (always a Delaunay edge).
    ApexSearch search(sites, tree);
    const Box& box = sites.bounds;
    const std::int32_t s = search.site_nearest_to({0.5 * box.min_x + 0.5 * box.max_x, 0.5 * box.min_y + 0.5 * box.max_y});
    growth.seed(s, search.nearest_site(s));
    return 2;
  }
  std::size_t queued = 0;
  const auto open_link = [&](std::int64_t link) {
    const Triangle& tri = mesh.triangles[static_cast<std::size_t>(triangle_of(link))];
    const std::int32_t x = tri[(slot_of(link) + 1) % 3], y = tri[(slot_of(link) + 2) % 3];
    if (growth.open(y, x, link)) ++queued;
  };
  if (mesh.open_slots) {
    // The backend listed them (in triangle order, as find_open_links finds them).
    for (const std::int64_t slot : *mesh.open_slots) {
      const auto t = static_cast<std::size_t>(slot / 3);
      const int k = static_cast<int>(slot % 3);
      if (slot < 0 || t >= mesh.triangles.size() || mesh.neighbors[t][static_cast<std::size_t>(k)] != no_neighbor)
        throw Error(ErrorCode::internal, "the backend listed a link as open that is not");
      open_link(pack(static_cast<std::int32_t>(t), k));
    }
    return queued;
  }
  for (const auto& links : find_open_links(mesh)) {
    for (const std::int64_t link : links) open_link(link);
  }
  return queued;
}

}  // namespace

std::vector<TriangleNeighbors> derive_neighbors(const std::vector<Triangle>& triangles) {
  // Around vertex v, the edge v->w of one triangle pairs with the edge w->v of another. Corners
  // (triangle * 3 + slot) are distributed by vertex block, stably (each chunk of triangles
  // counts, then scatters); each block then files its corners by vertex and matches each pair
  // once, at its smaller vertex. Every link is written by exactly one thread; no atomics.
  const std::size_t count = triangles.size();
  std::vector<TriangleNeighbors> neighbors;
  resize_prefaulted(neighbors, count);
  const std::size_t chunks = chunk_count(count);
  std::vector<std::int32_t> largest(chunks, -1);
  parallel_chunks(count, chunks, [&](std::size_t chunk, std::size_t begin, std::size_t end) {
    std::int32_t v_max = -1;
    for (std::size_t t = begin; t < end; ++t) {
      neighbors[t] = {no_neighbor, no_neighbor, no_neighbor};
      v_max = std::max({v_max, triangles[t][0], triangles[t][1], triangles[t][2]});
    }
    largest[chunk] = v_max;
  });
  const std::size_t vertices = static_cast<std::size_t>(*std::max_element(largest.begin(), largest.end()) + 1);
  if (vertices == 0) return neighbors;
  int block_bits = 12;  // a few hundred blocks: few scatter streams, blocks that fit in cache
  while ((vertices >> block_bits) > 512) ++block_bits;
  const std::size_t blocks = ((vertices - 1) >> block_bits) + 1;
  std::vector<std::uint32_t> next(chunks * blocks, 0);
  parallel_chunks(count, chunks, [&](std::size_t chunk, std::size_t begin, std::size_t end) {
    std::uint32_t* mine = next.data() + chunk * blocks;
    for (std::size_t t = begin; t < end; ++t) {
      for (const std::int32_t v : triangles[t]) ++mine[static_cast<std::uint32_t>(v) >> block_bits];
    }
  });
  const std::vector<std::size_t> block_start = distribution_slots(next, chunks, blocks);
  HostVector<std::int32_t> corners;
  resize_for_parallel_write(corners, 3 * count);
  parallel_chunks(count, chunks, [&](std::size_t chunk, std::size_t begin, std::size_t end) {
    std::uint32_t* mine = next.data() + chunk * blocks;
    for (std::size_t t = begin; t < end; ++t) {
      for (int k = 0; k < 3; ++k) {
        corners[mine[static_cast<std::uint32_t>(triangles[t][k]) >> block_bits]++] = static_cast<std::int32_t>(3 * t + k);
      }
    }
  });
  parallel_tasks(blocks, [&](std::size_t b) {
    const std::size_t first_vertex = b << block_bits;
    match_block_corners(triangles, corners.data() + block_start[b], block_start[b + 1] - block_start[b], first_vertex,
                        std::min(vertices - first_vertex, std::size_t{1} << block_bits), neighbors);
  });
  return neighbors;
}

SeamStats complete_seam(const SiteSet& sites, const Hull& hull, const BucketTree& tree,
                        PartialTriangulation& mesh, const std::function<void()>& before_growth) {
  Stopwatch phase;
  if (mesh.neighbors.size() != mesh.triangles.size()) {
    mesh.neighbors = derive_neighbors(mesh.triangles);
    mesh.open_slots.reset();  // listed for an adjacency that is gone
  }
  const std::size_t expected = 2 * static_cast<std::size_t>(sites.size()) - hull.sites.size() - 2;
  reserve_prefaulted(mesh.triangles, expected);
  reserve_prefaulted(mesh.neighbors, expected);

  SeamStats stats;
  stats.setup_ms = phase.ms();
  phase.restart();
  FrontGrowth growth(sites, hull, tree, mesh);
  stats.open_edges = queue_front(sites, tree, mesh, growth);
  stats.open_ms = phase.ms();
  if (before_growth) before_growth();
  phase.restart();
  growth.grow();
  stats.grow_ms = phase.ms();
  stats.triangles_made = growth.made();
  stats.candidates_tested = growth.candidates_tested();
  if (mesh.triangles.size() != expected) {
    throw Error(ErrorCode::internal, "seam completion made " + std::to_string(mesh.triangles.size()) +
                                         " triangles, expected 2n - h - 2 = " + std::to_string(expected));
  }
  return stats;
}

}  // namespace expanse::detail
