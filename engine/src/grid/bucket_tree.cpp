#include "grid/bucket_tree.hpp"

#include "expanse/error.hpp"
#include "input/morton.hpp"
#include "input/parallel.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cmath>
#include <numeric>
#include <utility>

namespace expanse::detail {
namespace {

using Node = BucketTree::Node;

bool is_bucket(const Node& node, int capacity) {
  return node.end - node.begin <= capacity || node.size == 1;
}

// The four children of a node that splits. Within the node all higher code bits are equal, so
// the two bits of its level are sorted: each quadrant is a contiguous range (Morton order:
// (0,0), (1,0), (0,1), (1,1)). code(i) is site i's code.
template <class Code>
std::array<Node, 4> children_of(const Node& parent, const Code& code) {
  const std::uint32_t half = parent.size / 2;
  int shift = 0;
  while ((1u << shift) < half) ++shift;
  std::array<Node, 4> children;
  std::int32_t lo = parent.begin;
  for (int quadrant = 0; quadrant < 4; ++quadrant) {
    // First site in [lo, end) whose quadrant is above this one (partition point).
    std::int32_t first = lo, last = parent.end;
    while (first < last) {
      const std::int32_t mid = first + (last - first) / 2;
      if (static_cast<int>((code(mid) >> (2 * shift)) & 3u) <= quadrant) first = mid + 1;
      else last = mid;
    }
    children[quadrant] = {parent.x0 + ((quadrant & 1) ? half : 0), parent.y0 + ((quadrant & 2) ? half : 0), half, -1,
                          lo, first};
    lo = first;
  }
  return children;
}

// The descendants of `parent` in depth-first order (four children together, then each child's
// subtree in turn), written from out[cursor] on (out == nullptr: only counted); returns
// parent's first child's index, or -1 for a bucket.
template <class Code>
std::int32_t grow(Node* out, std::size_t& cursor, const Node& parent, const Code& code, int capacity) {
  if (is_bucket(parent, capacity)) return -1;
  const std::size_t first = cursor;
  cursor += 4;
  const std::array<Node, 4> children = children_of(parent, code);
  for (int quadrant = 0; quadrant < 4; ++quadrant) {
    const std::int32_t child_first = grow(out, cursor, children[quadrant], code, capacity);
    if (out) {
      out[first + quadrant] = children[quadrant];
      out[first + quadrant].first_child = child_first;
    }
  }
  return static_cast<std::int32_t>(first);
}

// Deepest level (root: 0, size 2^30) of a node holding both codes, at most 29 (a node of size
// 1 never splits).
int shared_level(std::uint64_t a, std::uint64_t b) {
  const std::uint64_t x = a ^ b;
  if (x == 0) return 29;
  const int bits = static_cast<int>(std::bit_width(x));
  return std::min(29, BucketTree::quant_bits - (bits + 1) / 2);
}

// Nodes below a node at `level` holding sites [0, m) with these sorted codes (four per node
// that splits, itself included), without building them: a node splits when it holds sites i
// and i + capacity; the sites i for which a given node splits are consecutive, so it is
// counted at the first of them.
std::size_t count_descendants(const std::uint64_t* codes, std::size_t m, int level, int capacity) {
  const auto span = static_cast<std::size_t>(capacity);
  std::size_t splits = 0;
  int previous = level - 1;
  for (std::size_t i = 0; i + span < m; ++i) {
    const int deepest = shared_level(codes[i], codes[i + span]);
    const int known = i == 0 ? level - 1 : std::max(level - 1, std::min(previous, shared_level(codes[i - 1], codes[i])));
    if (deepest > known) splits += static_cast<std::size_t>(deepest - known);
    previous = deepest;
  }
  return 4 * splits;
}

// The top of the tree, split on one thread breadth first down to subtrees small enough to be
// tasks (their placement, later, is depth first).
struct TopSplit {
  struct Top {
    Node node;
    std::int32_t first_top = -1;  // four children in `tops`
    std::int32_t task = -1;
  };
  std::vector<Top> tops;
  std::vector<std::int32_t> tasks;  // top index of each task's root
};

template <class Code>
TopSplit split_top(std::int32_t n, int capacity, const Code& code_of) {
  const auto count = static_cast<std::size_t>(n);
  const std::size_t task_sites = std::max<std::size_t>(std::size_t{1} << 13, count / (16 * host_threads()));
  TopSplit split;
  auto& tops = split.tops;
  tops.push_back({{0, 0, 1u << BucketTree::quant_bits, -1, 0, n}});
  for (std::size_t t = 0; t < tops.size(); ++t) {
    const Node node = tops[t].node;
    if (is_bucket(node, capacity)) continue;
    if (static_cast<std::size_t>(node.end - node.begin) <= task_sites) {
      tops[t].task = static_cast<std::int32_t>(split.tasks.size());
      split.tasks.push_back(static_cast<std::int32_t>(t));
      continue;
    }
    tops[t].first_top = static_cast<std::int32_t>(tops.size());
    for (const Node& child : children_of(node, code_of)) tops.push_back({child});
  }
  return split;
}

// Buckets are ranges of site ids: that needs the Morton order prepare_sites() establishes.
// Each task checks its own sites; the ranges of the top's buckets and tasks cover [0, n) in
// order, so the top's own sites and the joins between ranges are checked here.
template <class Code>
bool top_in_morton_order(const TopSplit& split, std::int32_t n, const Code& code_of) {
  for (const TopSplit::Top& top : split.tops) {
    if (top.first_top >= 0) continue;
    if (top.node.begin > 0 && top.node.begin < n && code_of(top.node.begin - 1) > code_of(top.node.begin)) return false;
    if (top.task >= 0) continue;
    for (std::int32_t i = top.node.begin + 1; i < top.node.end; ++i) {
      if (code_of(i - 1) > code_of(i)) return false;
    }
  }
  return true;
}

}  // namespace

BucketTree::BucketTree(const SiteSet& sites, int capacity) : capacity_(std::max(1, capacity)) {
  const Quantiser quantiser(sites.bounds);
  origin_x_ = quantiser.origin_x;
  origin_y_ = quantiser.origin_y;
  scale_ = quantiser.scale;

  // Each task's subtree counted, then written where a sequential depth-first split puts it: a
  // subtree's nodes are contiguous there, after those of the subtrees before it. Codes are
  // computed where they are needed (in cache for a task's sites) rather than stored for every
  // site.
  const std::int32_t n = sites.size();
  const auto code_of = [&](std::int32_t i) {
    const Point2& p = sites.points[static_cast<std::size_t>(i)];
    return morton_code(quantise_x(p.x), quantise_y(p.y));
  };
  const TopSplit split = split_top(n, capacity_, code_of);
  const auto& tops = split.tops;
  const auto& tasks = split.tasks;
  std::atomic<bool> sorted{top_in_morton_order(split, n, code_of)};
  std::vector<std::size_t> task_nodes(tasks.size());
  // One task's codes, in cache: the same on both passes.
  const auto task_codes = [&](const Node& root) {
    thread_local std::vector<std::uint64_t> codes;
    codes.resize(static_cast<std::size_t>(root.end - root.begin));
    for (std::int32_t i = root.begin; i < root.end; ++i) codes[static_cast<std::size_t>(i - root.begin)] = code_of(i);
    return [data = codes.data(), base = root.begin](std::int32_t i) -> const std::uint64_t& { return data[i - base]; };
  };
  parallel_tasks(tasks.size(), [&](std::size_t task) {
    const Node& root = tops[tasks[task]].node;
    const auto code = task_codes(root);
    for (std::int32_t i = root.begin + 1; i < root.end; ++i) {
      if (code(i - 1) > code(i)) sorted.store(false, std::memory_order_relaxed);
    }
    int level = 0;
    while ((root.size << level) < (1u << quant_bits)) ++level;
    task_nodes[task] = count_descendants(&code(root.begin), static_cast<std::size_t>(root.end - root.begin), level,
                                          capacity_);
  });
  if (!sorted.load()) {
    throw Error(ErrorCode::internal, "bucket tree built over sites that are not in Morton order");
  }
  std::size_t total = 1;
  for (const auto& top : tops) total += top.first_top >= 0 ? 4 : 0;
  for (const std::size_t nodes : task_nodes) total += nodes;
  nodes_.resize(total);
  nodes_[0] = tops[0].node;
  std::vector<std::size_t> task_offset(tasks.size());
  std::size_t cursor = 1;
  const auto place = [&](auto&& self, std::size_t t, std::size_t index) -> void {
    const auto& top = tops[t];
    if (top.first_top >= 0) {
      const std::size_t first = cursor;
      cursor += 4;
      nodes_[index].first_child = static_cast<std::int32_t>(first);
      for (int k = 0; k < 4; ++k) nodes_[first + k] = tops[top.first_top + k].node;
      for (int k = 0; k < 4; ++k) self(self, top.first_top + k, first + k);
    } else if (top.task >= 0) {
      task_offset[top.task] = cursor;
      if (task_nodes[top.task] > 0) nodes_[index].first_child = static_cast<std::int32_t>(cursor);
      cursor += task_nodes[top.task];
    }
  };
  place(place, 0, 0);
  // Large buckets make few nodes: building them computes codes where it searches, instead of
  // computing every site's code a second time.
  const bool few_nodes = capacity_ >= 64;
  parallel_tasks(tasks.size(), [&](std::size_t task) {
    const Node& root = tops[tasks[task]].node;
    std::size_t at = task_offset[task];
    if (few_nodes) {
      grow(nodes_.data(), at, root, code_of, capacity_);
    } else {
      grow(nodes_.data(), at, root, task_codes(root), capacity_);
    }
    if (at != task_offset[task] + task_nodes[task]) sorted.store(false);  // cannot happen: counted alike
  });
  if (!sorted.load()) throw Error(ErrorCode::internal, "bucket tree: a subtree has not the size it was counted at");
  index_cells(static_cast<std::size_t>(n));
}

void BucketTree::index_cells(std::size_t count) {
  // About half a bucket (four sites for 8-site buckets) per cell when sites are spread evenly.
  // Every cell is covered by exactly one node of cell size or one bucket above it; the
  // subtrees a few levels down fill disjoint blocks of cells, in parallel.
  const std::size_t per_cell = std::max(1, capacity_ / 2);
  while (grid_level_ < 12 && (std::size_t{1} << (2 * grid_level_)) * per_cell < count) ++grid_level_;
  cell_node_.resize(std::size_t{1} << (2 * grid_level_));
  std::vector<std::int32_t> roots{0};
  for (int level = 0; level < 4; ++level) {
    std::vector<std::int32_t> deeper;
    for (const std::int32_t r : roots) {
      const Node& node = nodes_[r];
      if (node.first_child >= 0 && node.size > (1u << cell_shift())) {
        for (int k = 0; k < 4; ++k) deeper.push_back(node.first_child + k);
      } else {
        fill_cells(r);
      }
    }
    roots.swap(deeper);
  }
  parallel_tasks(roots.size(), [&](std::size_t r) { fill_cells(roots[r]); });
}

BucketTree BucketTree::on_demand(const SiteSet& sites, int capacity) {
  BucketTree tree;
  const Quantiser quantiser(sites.bounds);
  tree.origin_x_ = quantiser.origin_x;
  tree.origin_y_ = quantiser.origin_y;
  tree.scale_ = quantiser.scale;
  tree.capacity_ = std::max(1, capacity);
  tree.sites_ = &sites;
  const Node root{0, 0, 1u << quant_bits, -1, 0, sites.size()};
  tree.nodes_.push_back(root);
  tree.tight_.push_back(tree.tight_box(root));
  tree.nodes_[0].first_child = is_bucket(root, tree.capacity_) ? -1 : unsplit;
  if (tree.nodes_[0].first_child == -1) tree.check_bucket(0);
  // Cells of a few hundred sites: the grid is filled cell by cell as searches enter it, and is
  // kept small (at most 2^18 cells, 1 MB), since it is written whole.
  const std::size_t per_cell = std::max(64, tree.capacity_ / 2);
  const auto count = static_cast<std::size_t>(sites.size());
  while (tree.grid_level_ < 9 && (std::size_t{1} << (2 * tree.grid_level_)) * per_cell < count) ++tree.grid_level_;
  tree.cell_node_.assign(std::size_t{1} << (2 * tree.grid_level_), -1);
  return tree;
}

std::int32_t BucketTree::split(std::int32_t index) const {
  const SiteSet& sites = *sites_;
  const auto code_of = [&](std::int32_t i) {
    const Point2& p = sites.points[static_cast<std::size_t>(i)];
    return morton_code(quantise_x(p.x), quantise_y(p.y));
  };
  const Node parent = nodes_[static_cast<std::size_t>(index)];
  const std::array<Node, 4> children = children_of(parent, code_of);
  const auto first = static_cast<std::int32_t>(nodes_.size());
  for (Node child : children) {
    child.first_child = is_bucket(child, capacity_) ? -1 : unsplit;
    nodes_.push_back(child);
    tight_.push_back(tight_box(child));
  }
  nodes_[static_cast<std::size_t>(index)].first_child = first;
  for (int k = 0; k < 4; ++k) {
    if (nodes_[static_cast<std::size_t>(first + k)].first_child == -1) check_bucket(first + k);
  }
  return first;
}

QuantBox BucketTree::tight_box(const Node& node) const {
  if (node.end - node.begin > tight_box_sites || node.begin == node.end) return node.box();
  QuantBox box{quant_max, quant_max, 0, 0};
  for (std::int32_t i = node.begin; i < node.end; ++i) {
    const Point2& p = sites_->points[static_cast<std::size_t>(i)];
    const std::uint32_t qx = quantise_x(p.x), qy = quantise_y(p.y);
    box = {std::min(box.x0, qx), std::min(box.y0, qy), std::max(box.x1, qx), std::max(box.y1, qy)};
  }
  return box;
}

void BucketTree::check_bucket(std::int32_t index) const {
  // The split found each child's range by binary search, which is right only over sites in
  // Morton order: every site of a bucket must lie in its box, in code order.
  const SiteSet& sites = *sites_;
  const Node& bucket = nodes_[static_cast<std::size_t>(index)];
  const QuantBox box = bucket.box();
  std::uint64_t previous = 0;
  for (std::int32_t i = bucket.begin; i < bucket.end; ++i) {
    const Point2& p = sites.points[static_cast<std::size_t>(i)];
    const std::uint32_t qx = quantise_x(p.x), qy = quantise_y(p.y);
    const std::uint64_t code = morton_code(qx, qy);
    if (qx < box.x0 || qx > box.x1 || qy < box.y0 || qy > box.y1 || (i > bucket.begin && code < previous)) {
      throw Error(ErrorCode::internal, "bucket tree built over sites that are not in Morton order");
    }
    previous = code;
  }
}

std::int32_t BucketTree::resolve_cell(int i, int j) const {
  // The node of cell size over cell (i, j), or the bucket above it, found from the root.
  const int shift = cell_shift();
  const std::uint32_t qx = static_cast<std::uint32_t>(i) << shift, qy = static_cast<std::uint32_t>(j) << shift;
  std::int32_t node = 0;
  while (nodes_[static_cast<std::size_t>(node)].size > (1u << shift)) {
    const std::int32_t first = children(node);
    if (first < 0) break;
    const Node& parent = nodes_[static_cast<std::size_t>(node)];
    const std::uint32_t half = parent.size / 2;
    node = first + ((qx >= parent.x0 + half ? 1 : 0) | (qy >= parent.y0 + half ? 2 : 0));
  }
  cell_node_[(static_cast<std::size_t>(j) << grid_level_) + i] = node;
  return node;
}

void BucketTree::fill_cells(std::int32_t node_index) {
  const Node& node = nodes_[node_index];
  const int shift = cell_shift();
  if (node.first_child >= 0 && node.size > (1u << shift)) {
    for (int k = 0; k < 4; ++k) fill_cells(node.first_child + k);
    return;
  }
  // A node of cell size, or a bucket covering several cells.
  const std::uint32_t i0 = node.x0 >> shift, j0 = node.y0 >> shift;
  const std::uint32_t cells = std::max<std::uint32_t>(1, node.size >> shift);
  for (std::uint32_t j = j0; j < j0 + cells; ++j) {
    for (std::uint32_t i = i0; i < i0 + cells; ++i) cell_node_[(static_cast<std::size_t>(j) << grid_level_) + i] = node_index;
  }
}

std::uint32_t BucketTree::bucket_size_at(std::uint32_t qx, std::uint32_t qy) const {
  std::int32_t node = cell_node(static_cast<int>(qx >> cell_shift()), static_cast<int>(qy >> cell_shift()));
  for (std::int32_t first = children(node); first >= 0; first = children(node)) {
    const Node& parent = nodes_[node];
    const std::uint32_t half = parent.size / 2;
    const int quadrant = (qx >= parent.x0 + half ? 1 : 0) | (qy >= parent.y0 + half ? 2 : 0);
    node = first + quadrant;
  }
  return nodes_[node].size;
}

}  // namespace expanse::detail
