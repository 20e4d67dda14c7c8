#include "grid/bucket_tree.hpp"

#include "expanse/error.hpp"
#include "input/morton.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <utility>

namespace expanse::detail {

BucketTree::BucketTree(const SiteSet& sites) {
  const Quantiser quantiser(sites.bounds);
  origin_x_ = quantiser.origin_x;
  origin_y_ = quantiser.origin_y;
  scale_ = quantiser.scale;

  const std::int32_t n = sites.size();
  std::vector<std::uint64_t> codes(n);
  for (std::int32_t i = 0; i < n; ++i) {
    const Point2& p = sites.points[i];
    codes[i] = morton_code(quantise_x(p.x), quantise_y(p.y));
  }
  // Buckets are ranges of site ids: that needs the Morton order prepare_sites() establishes.
  if (!std::is_sorted(codes.begin(), codes.end())) {
    throw Error(ErrorCode::internal, "bucket tree built over sites that are not in Morton order");
  }
  nodes_.reserve(static_cast<std::size_t>(n) / 2 + 16);
  nodes_.push_back({0, 0, 1u << quant_bits, -1, 0, n});
  split(0, codes);

  // About four sites per cell when they are spread evenly.
  while (grid_level_ < 12 && (std::size_t{1} << (2 * grid_level_)) * 4 < static_cast<std::size_t>(n)) ++grid_level_;
  cell_node_.assign(std::size_t{1} << (2 * grid_level_), 0);
  fill_cells(0);
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
  while (nodes_[node].first_child >= 0) {
    const Node& parent = nodes_[node];
    const std::uint32_t half = parent.size / 2;
    const int quadrant = (qx >= parent.x0 + half ? 1 : 0) | (qy >= parent.y0 + half ? 2 : 0);
    node = parent.first_child + quadrant;
  }
  return nodes_[node].size;
}

void BucketTree::split(std::int32_t node, const std::vector<std::uint64_t>& codes) {
  const Node parent = nodes_[node];
  if (parent.end - parent.begin <= bucket_capacity || parent.size == 1) return;
  const auto first_child = static_cast<std::int32_t>(nodes_.size());
  nodes_[node].first_child = first_child;
  nodes_.resize(nodes_.size() + 4);
  // Within this node all higher code bits are equal, so the two bits of this level are sorted:
  // each quadrant is a contiguous range (Morton order: (0,0), (1,0), (0,1), (1,1)).
  const std::uint32_t half = parent.size / 2;
  int shift = 0;
  while ((1u << shift) < half) ++shift;
  const auto quadrant_of = [&](std::uint64_t code) { return static_cast<int>((code >> (2 * shift)) & 3u); };
  std::int32_t lo = parent.begin;
  for (int quadrant = 0; quadrant < 4; ++quadrant) {
    const auto it = std::partition_point(codes.begin() + lo, codes.begin() + parent.end,
                                         [&](std::uint64_t c) { return quadrant_of(c) <= quadrant; });
    const auto hi = static_cast<std::int32_t>(it - codes.begin());
    nodes_[first_child + quadrant] = {parent.x0 + ((quadrant & 1) ? half : 0),
                                      parent.y0 + ((quadrant & 2) ? half : 0), half, -1, lo, hi};
    lo = hi;
  }
  for (int quadrant = 0; quadrant < 4; ++quadrant) split(first_child + quadrant, codes);
}

}  // namespace expanse::detail
