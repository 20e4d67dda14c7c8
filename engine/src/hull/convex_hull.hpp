#pragma once
// Convex hull of the sites, known before any growth: hull edges have no apex, so no search
// ever looks for one.
#include <cstdint>
#include <span>
#include <vector>

#include "input/parallel.hpp"
#include "input/site_set.hpp"

namespace expanse::detail {

struct Hull {
  /// Sites on the hull, counter-clockwise, collinear hull sites included. When every site lies
  /// on one line (collinear == true): all sites sorted along the line.
  std::vector<std::int32_t> sites;
  bool collinear = false;
  /// predecessor[s]: the hull site before s in CCW order, or -1 when s is not on the hull.
  HostVector<std::int32_t> predecessor;

  /// True for the directed edge a->b that has no site on its left, i.e. a hull edge walked
  /// clockwise (b == predecessor[a]). Such an edge never has an apex.
  bool is_outer_edge(std::int32_t a, std::int32_t b) const { return predecessor[a] == b; }
};

/// Exact convex hull (monotone chain with exact orientation).
Hull convex_hull(const SiteSet& sites);

/// The hull of the raw input, as convex_hull(prepare_sites(input)) finds it, in input indices.
struct InputHull {
  /// The same hull sites in the same order (CCW from the same first site; with collinear, every
  /// distinct point sorted along the line), each named by its representative: the smallest input
  /// index among the points equal to it.
  std::vector<std::int32_t> sites;
  bool collinear = false;
};

/// For a backend that sorts and merges on its device: the hull without a SiteSet, from the
/// scaled input points (the same values every predicate of convex_hull sees), through the same
/// prefilter (one parallel pass over the input) and the same monotone chain over the few
/// candidates, their duplicates merged. Precondition: `scan` is scan_input(input) (every point
/// finite).
InputHull convex_hull_of_input(std::span<const Point2> input, const InputScan& scan);

}  // namespace expanse::detail
