#pragma once
// The one primitive on the host, apex_search(a->b) over the bucket tree (docs/algorithm.md),
// and the nearest-site search that starts a walk.
#include <cstdint>
#include <vector>

#include "grid/bucket_tree.hpp"
#include "predicates/apex_filter.hpp"
#include "input/site_set.hpp"

namespace expanse::detail {

/// The searches of one thread: the tree and the sites are shared (read only), the stack and
/// the state of the search under way are this object's.
class ApexSearch {
 public:
  ApexSearch(const SiteSet& sites, const BucketTree& tree) : sites_(sites), tree_(tree) {}

  /// The site c strictly left of a->b whose perturbed circle(a, b, c) holds no other site, or
  /// -1 if no site lies strictly left. Precondition: a != b.
  std::int32_t apex_search(std::int32_t a, std::int32_t b);

  /// The site nearest to site s (exact comparison of squared distances), -1 if s is alone.
  std::int32_t nearest_site(std::int32_t s);

  /// The site nearest to an arbitrary point (exactly), -1 if there are no sites.
  std::int32_t site_nearest_to(const Point2& q) { return nearest(q, -1); }

  /// Sites tested against a predicate so far (for stats and benchmarks).
  std::uint64_t candidates_tested() const { return candidates_tested_; }

 private:
  /// The circle region: the bounding box of circle(a, b, c) ∩ left half-plane, enlarged by a
  /// proven error bound, and the circle itself, for pruning the tree's nodes.
  struct CircleRegion {
    double x0, y0, x1, y1;  // real coordinates (infinite when the circle is unreliable)
    QuantBox quant;         // the same box, quantised
    double cx, cy, reach;   // the circle, its radius enlarged by every error bound (reach < 0:
                            // unreliable, no circle test)
  };
  /// The edge of the search under way, in the forms its tests read.
  struct Query {
    std::int32_t ia, ib;
    Point2 a, b;
    double dx, dy;              // b - a
    std::uint32_t qmx, qmy;     // the quantised midpoint, where the search starts
    exact::ApexEdge edge;
  };
  /// Its best candidate so far, with the circle region it leaves.
  struct Best {
    std::int32_t site;
    Point2 point;
    double lambda, error;  // λ (see scan_bucket) and its forward error bound
    exact::ApexLift lift;  // valid once site >= 0
    CircleRegion region;
  };

  void start_search(std::int32_t a, std::int32_t b);
  /// Visits every bucket that meets `square` but not the previous round's square.
  void scan_box(const QuantBox& square);
  void descend(std::int32_t root, const QuantBox& square);
  void visit_bucket(std::int32_t index, const BucketTree::Node& node, const QuantBox& box);
  /// Tests the bucket's candidates; true when one of them became the best.
  bool scan_bucket(const BucketTree::Node& node);
  /// Whether the candidate is strictly left of the edge and beats the best so far.
  bool improves(std::int32_t i, const Point2& p);
  /// What the filters left open: p inside the best candidate's perturbed circle, exactly.
  bool decide_exactly(const Point2& p) const;
  void update_circle_region();

  std::int32_t nearest(const Point2& q, std::int32_t exclude);
  /// The circle region of circle(a, b, c).
  CircleRegion circle_region(const Point2& a, const Point2& b, const Point2& c) const;
  /// The circle region of the circle with centre a + (ux, uy), given forward error bounds of
  /// the centre.
  CircleRegion circle_region_around(const Point2& a, const Point2& b, double ux, double uy, double ux_error,
                                    double uy_error) const;
  bool outside_circle(const QuantBox& box, const CircleRegion& region) const;
  QuantBox square_around(std::uint32_t qx, std::uint32_t qy, std::uint64_t half) const;
  bool entirely_right(const QuantBox& box, const Point2& a, const Point2& b) const;
  /// True when no point of the box lies inside circle(a, b, c), c's lift given: the test of
  /// outside_circle without the circle's centre, which a sliver's huge radius makes useless.
  bool outside_lifted_circle(const QuantBox& box, const Point2& a, const exact::ApexLift& c) const;

  const SiteSet& sites_;
  const BucketTree& tree_;
  Query query_{};
  Best best_{};
  QuantBox visited_{};  // the previous round's square, its buckets all scanned or pruned
  bool has_visited_ = false;
  std::vector<std::int32_t> stack_;
  std::vector<std::int32_t> big_buckets_;  // buckets spanning several cells, scanned this search
  std::uint64_t candidates_tested_ = 0;
};

/// Sign of |q - p1|^2 - |q - p2|^2, exactly.
int compare_squared_distance(const Point2& q, const Point2& p1, const Point2& p2);

}  // namespace expanse::detail
