#pragma once
// Buckets for the apex search on the host: a quadtree over Morton-sorted sites whose leaves
// (buckets) hold at most a few sites, so dense clusters get small buckets and sparse regions
// large ones. All box tests run on quantised integer coordinates: quantisation is monotone in
// the real coordinates, so a site can never hide outside the box it is tested against.
#include <cstdint>
#include <vector>

#include "input/parallel.hpp"
#include "input/site_set.hpp"

namespace expanse::detail {

/// Integer box [x0, x1] x [y0, y1] in quantised coordinates (inclusive).
struct QuantBox {
  std::uint32_t x0, y0, x1, y1;
  bool intersects(const QuantBox& o) const {
    return x0 <= o.x1 && o.x0 <= x1 && y0 <= o.y1 && o.y0 <= y1;
  }
  bool contains(const QuantBox& o) const {
    return x0 <= o.x0 && o.x1 <= x1 && y0 <= o.y0 && o.y1 <= y1;
  }
};

class BucketTree {
 public:
  static constexpr int quant_bits = 30;
  static constexpr std::uint32_t quant_max = (1u << quant_bits) - 1;
  static constexpr int bucket_capacity = 8;

  /// Node::first_child of a node that holds more than a bucket's sites but has not been split
  /// yet (only in a tree made by on_demand()): children() splits it.
  static constexpr std::int32_t unsplit = -2;

  struct Node {
    std::uint32_t x0, y0;  // quantised lower-left corner
    std::uint32_t size;    // side length in quanta (a power of two)
    std::int32_t first_child;  // index of 4 consecutive children, -1 for a bucket, or unsplit
    std::int32_t begin, end;   // range of site ids (sites are in Morton order)
    QuantBox box() const { return {x0, y0, x0 + (size - 1), y0 + (size - 1)}; }
  };

  /// Precondition: sites as prepare_sites() returns them (in Morton order); throws
  /// Error(internal) otherwise. The tree refers to the sites by id, it keeps no copy.
  /// Buckets hold at most `capacity` sites (unless they are a single quantum); larger buckets
  /// make a much smaller tree that costs each search more (see coarse_capacity).
  /// Sites must outlive the tree when it is made on_demand.
  explicit BucketTree(const SiteSet& sites, int capacity = bucket_capacity);

  /// The tree the seam stage searches to make `missing` triangles among `sites` sites: when the
  /// seam is small next to the sites (a GPU leaves ~100 triangles out of 33.5M), one built on
  /// demand, since building a whole tree costs far more than the seam's searches (even with
  /// coarse_capacity buckets: 325 ms at 4096^2 on the 2-core VM, against a 25 ms seam);
  /// otherwise the full tree with 8-site buckets, built on all threads. The crossover: at 1M
  /// sites on the 2-core VM the full tree takes 9.1 ms to build and then 0.63 us a seam
  /// triangle, the on-demand tree 1.7 us a triangle (4009 triangles: 11.6 against 6.9 ms), so
  /// on demand pays up to about n / 118 missing triangles.
  static BucketTree for_seam(const SiteSet& sites, std::size_t missing) {
    const auto count = static_cast<std::size_t>(sites.size());
    return missing > 0 && missing <= count / 128 ? on_demand(sites) : BucketTree(sites);
  }
  /// Large buckets: a tree about 27 times smaller than with 8-site buckets, whose searches cost
  /// more (what the seam stage used before on_demand; benchmarks compare).
  static constexpr int coarse_capacity = 256;

  /// A tree that splits a node only when a search first looks inside it: nothing of size n is
  /// built, so a seam of a few dozen triangles costs in proportion to the sites its searches
  /// reach, not to all sites (a GPU leaves ~100 of 16.8M). Searches grow it, so one search at a
  /// time (the seam stage runs on one thread). Morton order, which the full build checks for
  /// every site, is checked here for the sites of each bucket it makes: the ones searched.
  static BucketTree on_demand(const SiteSet& sites, int capacity = bucket_capacity);
  bool is_on_demand() const { return sites_ != nullptr; }

  int capacity() const { return capacity_; }

  /// nodes()[index].first_child, after splitting the node if it is unsplit. Splitting appends
  /// to nodes(): references to its elements do not survive this call; indices do.
  std::int32_t children(std::int32_t index) const {
    const std::int32_t first = nodes_[static_cast<std::size_t>(index)].first_child;
    return first == unsplit ? split(index) : first;
  }

  /// The box a search tests node `index` by: in an on-demand tree, for nodes of at most
  /// tight_box_sites sites, the box of the sites' own quantised coordinates; otherwise the
  /// node's square. Every site of the node lies in it (quantisation is monotone). Searches
  /// must use one kind of box throughout (which nodes a round already covered is decided with
  /// it). Why: the triangles a GPU leaves to the seam stage hug the hull, and their searches
  /// follow a strip along it a few ulps wide and most of the domain long; the squares of every
  /// node along the strip meet it, while almost no node holds a site inside it. The bound: at
  /// 4096^2 with the sites the CUDA kernel defers (2-core VM), seam growth took 13.4 ms with
  /// squares only, 8.2 / 7.8 / 8.4 / 14.0 ms with tight boxes up to 64 / 512 / 4096 / 32768
  /// sites (larger nodes' boxes cost more to find than they save).
  QuantBox search_box(std::int32_t index) const {
    return tight_.empty() ? nodes_[static_cast<std::size_t>(index)].box() : tight_[static_cast<std::size_t>(index)];
  }
  static constexpr std::int32_t tight_box_sites = 512;

  /// Quantised coordinate of a real one; monotone, clamped to [0, quant_max].
  std::uint32_t quantise_x(double x) const { return quantise(x - origin_x_); }
  std::uint32_t quantise_y(double y) const { return quantise(y - origin_y_); }
  /// Real lower bound of quantum q (for conservative geometric pruning only).
  double real_x(double q) const { return origin_x_ + q / scale_; }
  double real_y(double q) const { return origin_y_ + q / scale_; }
  double quantum() const { return 1.0 / scale_; }

  /// In the order a sequential depth-first split makes them (root first, then each node's four
  /// children together, each child's subtree before the next child's), whatever the threads.
  const HostVector<Node>& nodes() const { return nodes_; }
  /// Side (in quanta) of the bucket containing quantised point (qx, qy).
  std::uint32_t bucket_size_at(std::uint32_t qx, std::uint32_t qy) const;

  /// A uniform grid of cells over the tree at one level, for direct access where the sites
  /// are spread evenly: cell (i, j) names the tree node of that cell, or the bucket above it.
  int grid_cells_per_side() const { return 1 << grid_level_; }
  int cell_shift() const { return quant_bits - grid_level_; }  ///< quanta per cell = 2^shift
  std::int32_t cell_node(int i, int j) const {
    const std::int32_t node = cell_node_[(static_cast<std::size_t>(j) << grid_level_) + i];
    return node >= 0 ? node : resolve_cell(i, j);
  }

 private:
  // Must agree exactly with Quantiser (grid/morton.hpp).
  std::uint32_t quantise(double offset) const {
    const double q = offset * scale_;
    if (!(q > 0.0)) return 0;
    if (q >= static_cast<double>(quant_max)) return quant_max;
    return static_cast<std::uint32_t>(q);
  }
  BucketTree() = default;
  /// The grid of cells over the full tree (cell_node), for `count` sites.
  void index_cells(std::size_t count);
  void fill_cells(std::int32_t node);
  std::int32_t split(std::int32_t index) const;
  void check_bucket(std::int32_t index) const;
  QuantBox tight_box(const Node& node) const;  // search_box() of a new on-demand node
  std::int32_t resolve_cell(int i, int j) const;

  double origin_x_ = 0, origin_y_ = 0, scale_ = 1;
  int capacity_ = bucket_capacity;
  int grid_level_ = 0;
  // An on-demand tree grows while it is searched (split, resolve_cell); a full one never does.
  const SiteSet* sites_ = nullptr;  // on demand only
  mutable HostVector<std::int32_t> cell_node_;  // -1: not resolved yet (on demand only)
  mutable HostVector<Node> nodes_;
  mutable HostVector<QuantBox> tight_;  // search_box() of each node (on demand only)
};

}  // namespace expanse::detail
