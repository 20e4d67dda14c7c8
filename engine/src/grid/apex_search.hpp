#pragma once
// The one primitive, on the host: apex(a->b) over the bucket tree (DESIGN.md, docs/algorithm.md).
#include <cstdint>
#include <vector>

#include "grid/bucket_tree.hpp"
#include "predicates/apex_filter.hpp"
#include "input/site_set.hpp"

namespace expanse::detail {

class ApexSearch {
 public:
  ApexSearch(const SiteSet& sites, const BucketTree& tree) : sites_(sites), tree_(tree) {}

  /// The site c strictly left of a->b whose perturbed circle(a, b, c) holds no other site, or
  /// -1 if no site lies strictly left. Precondition: a != b.
  std::int32_t apex(std::int32_t a, std::int32_t b);

  /// The site nearest to site s (exact comparison of squared distances), -1 if s is alone.
  std::int32_t nearest_neighbor(std::int32_t s);

  /// The site nearest to an arbitrary point (exactly), -1 if there are no sites.
  std::int32_t nearest_site(const Point2& q) { return nearest(q, -1); }

  /// Sites tested against a predicate so far (for stats and benchmarks).
  std::uint64_t candidates_tested() const { return candidates_tested_; }

 private:
  std::int32_t nearest(const Point2& q, std::int32_t exclude);
  /// Bounding box of circle(a, b, c) ∩ left half-plane, enlarged by a proven error bound.
  struct Region {
    double x0, y0, x1, y1;  // real coordinates (infinite when the circle is unreliable)
    QuantBox quant;         // the same box, quantised
    double cx, cy, reach;   // the circle, its radius enlarged by every error bound (reach < 0:
                            // unreliable, no circle test)
  };
  /// The region of the circle with centre a + (ux, uy), given forward error bounds of the centre.
  Region circle_region(const Point2& a, const Point2& b, double ux, double uy, double ux_error,
                       double uy_error) const;
  bool outside_circle(const QuantBox& box, const Region& region) const;
  Region left_region_box(const Point2& a, const Point2& b, const Point2& c) const;
  QuantBox square_around(std::uint32_t qx, std::uint32_t qy, std::uint64_t half) const;
  bool entirely_right(const QuantBox& box, const Point2& a, const Point2& b) const;
  /// True when no point of the box lies inside circle(a, b, c), c's lift given: the test of
  /// outside_circle without the circle's centre, which a sliver's huge radius makes useless.
  bool outside_lifted_circle(const QuantBox& box, const Point2& a, const exact::ApexLift& c) const;

  const SiteSet& sites_;
  const BucketTree& tree_;
  std::vector<std::int32_t> stack_;
  std::vector<std::int32_t> big_buckets_;  // buckets spanning several cells, scanned this search
  std::uint64_t candidates_tested_ = 0;
};

/// Sign of |q - p1|^2 - |q - p2|^2, exactly.
int compare_squared_distance(const Point2& q, const Point2& p1, const Point2& p2);

}  // namespace expanse::detail
