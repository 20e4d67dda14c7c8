#include "grid/apex_search.hpp"

#include <gmp.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <limits>

#include "predicates/exact_arith.hpp"
#include "predicates/predicates.hpp"

namespace expanse::detail {
namespace {

constexpr double eps = DBL_EPSILON / 2;  // unit roundoff
constexpr QuantBox full_domain{0, 0, BucketTree::quant_max, BucketTree::quant_max};

int exact_compare_squared_distance(const Point2& q, const Point2& p1, const Point2& p2) {
  // (p1 - p2) . (p1 + p2 - 2q), in rationals: doubles convert to mpq exactly.
  mpq_t t[6], acc, tmp;
  const double values[6] = {q.x, q.y, p1.x, p1.y, p2.x, p2.y};
  for (int i = 0; i < 6; ++i) {
    mpq_init(t[i]);
    mpq_set_d(t[i], values[i]);
  }
  mpq_init(acc);
  mpq_init(tmp);
  auto term = [&](int q_i, int p1_i, int p2_i) {
    mpq_t diff, sum;
    mpq_init(diff);
    mpq_init(sum);
    mpq_sub(diff, t[p1_i], t[p2_i]);
    mpq_add(sum, t[p1_i], t[p2_i]);
    mpq_sub(sum, sum, t[q_i]);
    mpq_sub(sum, sum, t[q_i]);
    mpq_mul(diff, diff, sum);
    mpq_add(acc, acc, diff);
    mpq_clear(diff);
    mpq_clear(sum);
  };
  term(0, 2, 4);
  term(1, 3, 5);
  const int sign = mpq_sgn(acc);
  for (auto& v : t) mpq_clear(v);
  mpq_clear(acc);
  mpq_clear(tmp);
  return sign;
}

}  // namespace

int compare_squared_distance(const Point2& q, const Point2& p1, const Point2& p2) {
  const double ax = p1.x - q.x, ay = p1.y - q.y, bx = p2.x - q.x, by = p2.y - q.y;
  const double d1 = ax * ax + ay * ay, d2 = bx * bx + by * by;
  const double diff = d1 - d2;
  // Each squared distance carries a relative error below 4 eps (two subtractions, two squares,
  // one sum); 10 eps covers both plus the final subtraction.
  const double bound = 10 * eps * (d1 + d2);
  if (std::isfinite(diff) && std::fabs(diff) > bound && (d1 + d2) > 0x1p-900) {
    return diff > 0 ? 1 : -1;
  }
  return exact_compare_squared_distance(q, p1, p2);
}

QuantBox ApexSearch::square_around(std::uint32_t qx, std::uint32_t qy, std::uint64_t half) const {
  const auto lo = [&](std::uint32_t c) {
    return static_cast<std::uint32_t>(c > half ? c - half : 0);
  };
  const auto hi = [&](std::uint32_t c) {
    return static_cast<std::uint32_t>(std::min<std::uint64_t>(std::uint64_t{c} + half, BucketTree::quant_max));
  };
  return {lo(qx), lo(qy), hi(qx), hi(qy)};
}

bool ApexSearch::entirely_right(const QuantBox& box, const Point2& a, const Point2& b) const {
  // cross(b - a, p - a) is linear in p: its maximum over the box is at one corner. The box is
  // widened by a quantum each way so rounding in the quantisation cannot matter.
  const double dx = b.x - a.x, dy = b.y - a.y;
  const double q = tree_.quantum();
  const double x = dy < 0 ? tree_.real_x(static_cast<double>(box.x1) + 1) + q
                          : tree_.real_x(static_cast<double>(box.x0)) - q;
  const double y = dx > 0 ? tree_.real_y(static_cast<double>(box.y1) + 1) + q
                          : tree_.real_y(static_cast<double>(box.y0)) - q;
  const double px = x - a.x, py = y - a.y;
  const double cross = dx * py - dy * px;
  const double tolerance = 1e-9 * (std::fabs(dx) + std::fabs(dy)) * (std::fabs(px) + std::fabs(py));
  return cross < -tolerance;
}

bool ApexSearch::outside_lifted_circle(const QuantBox& box, const Point2& a, const exact::ApexLift& c) const {
  // In a's frame p lies inside circle(a, b, c) exactly when g(P) = Px Vx + Py Vy - |P|^2 K > 0
  // (apex_filter.hpp; K > 0, c being left of a->b). Over the box, g is at most the largest
  // value of its linear part (at a corner) less K times the least |P|^2. A sliver's circle,
  // whose radius may be 10^10 times the domain and whose centre is then known to no better than
  // the domain's width, is nearly a line here: this keeps the nodes beyond it out of the search.
  const double q = tree_.quantum();
  const double x0 = tree_.real_x(static_cast<double>(box.x0)) - q - a.x;
  const double x1 = tree_.real_x(static_cast<double>(box.x1) + 1) + q - a.x;
  const double y0 = tree_.real_y(static_cast<double>(box.y0)) - q - a.y;
  const double y1 = tree_.real_y(static_cast<double>(box.y1) + 1) + q - a.y;
  const double linear = std::max(c.vx * x0, c.vx * x1) + std::max(c.vy * y0, c.vy * y1);
  const double nx = std::max({x0, 0.0, -x1}), ny = std::max({y0, 0.0, -y1});
  const double mx = std::max(std::fabs(x0), std::fabs(x1)), my = std::max(std::fabs(y0), std::fabs(y1));
  const double upper = linear - std::max(c.k, 0.0) * (nx * nx + ny * ny);  // K > 0 exactly
  // The lift's rounding (apex_filter.hpp bounds it by 10 eps of the permanent), the corners'
  // subtraction of a, and this evaluation: far inside 1e-12 of the permanent over the box.
  const double permanent = mx * c.vx_perm + my * c.vy_perm + (mx * mx + my * my) * c.k_perm;
  return std::isfinite(upper) && std::isfinite(permanent) && upper < -(1e-12 * permanent + 1e-300);
}

ApexSearch::CircleRegion ApexSearch::circle_region(const Point2& a, const Point2& b, const Point2& c) const {
  // Circumcentre relative to a, with a forward error bound on each quantity: the box must hold
  // circle(a, b, c) ∩ left half-plane however the rounding fell.
  const double dx = b.x - a.x, dy = b.y - a.y, ex = c.x - a.x, ey = c.y - a.y;
  const double d2 = dx * dx + dy * dy, e2 = ex * ex + ey * ey;
  const double den = 2 * (dx * ey - dy * ex);
  const double den_error = 16 * eps * 2 * (std::fabs(dx * ey) + std::fabs(dy * ex));
  constexpr double inf = std::numeric_limits<double>::infinity();
  const CircleRegion everywhere{-inf, -inf, inf, inf, full_domain, 0, 0, -1};
  double ux, uy, ux_error, uy_error;
  // The rounded determinant only where its relative error is tiny: the centre's error is that
  // relative error times the radius, and a sliver's radius is many times the domain (a rotated
  // float grid's nearly collinear rows: searches of the whole domain, 95% of the seam's
  // candidates). Elsewhere the exact path below, whose error is a few ulps of the radius.
  if (den > 1e9 * den_error && std::isfinite(den)) {
    ux = (ey * d2 - dy * e2) / den;
    uy = (dx * e2 - ex * d2) / den;
    ux_error = (16 * eps * (std::fabs(ey) * d2 + std::fabs(dy) * e2) + std::fabs(ux) * den_error) / (den - den_error) +
               4 * eps * std::fabs(ux);
    uy_error = (16 * eps * (std::fabs(dx) * e2 + std::fabs(ex) * d2) + std::fabs(uy) * den_error) / (den - den_error) +
               4 * eps * std::fabs(uy);
  } else {
    // A nearly flat triangle: the rounded determinant is noise. Evaluate the circumcentre's
    // numerators and denominator exactly and round once, so near-collinear sites still get a
    // tight circle instead of a search of the whole domain.
    using namespace exact;
    const auto xd = exact_difference(b.x, a.x), yd = exact_difference(b.y, a.y);
    const auto xe = exact_difference(c.x, a.x), ye = exact_difference(c.y, a.y);
    const auto det = xd * ye - yd * xe;
    const auto dd = xd * xd + yd * yd;
    const auto ee = xe * xe + ye * ye;
    const double den_exact = 2 * det.approximate();
    if (!(den_exact > 0) || !std::isfinite(den_exact)) return everywhere;
    ux = (ye * dd - yd * ee).approximate() / den_exact;
    uy = (xd * ee - xe * dd).approximate() / den_exact;
    ux_error = 16 * eps * std::fabs(ux);
    uy_error = 16 * eps * std::fabs(uy);
  }
  return circle_region_around(a, b, ux, uy, ux_error, uy_error);
}

ApexSearch::CircleRegion ApexSearch::circle_region_around(const Point2& a, const Point2& b, double ux, double uy,
                                                          double ux_error, double uy_error) const {
  constexpr double inf = std::numeric_limits<double>::infinity();
  const CircleRegion everywhere{-inf, -inf, inf, inf, full_domain, 0, 0, -1};
  const double dx = b.x - a.x, dy = b.y - a.y;
  if (!std::isfinite(ux) || !std::isfinite(uy) || !std::isfinite(ux_error + uy_error)) return everywhere;
  const double r = std::sqrt(ux * ux + uy * uy);
  const double r_hi =
      std::sqrt((std::fabs(ux) + ux_error) * (std::fabs(ux) + ux_error) +
                (std::fabs(uy) + uy_error) * (std::fabs(uy) + uy_error)) * (1 + 8 * eps);
  const double cx = a.x + ux, cy = a.y + uy;
  const double cx_error = ux_error + 4 * eps * (std::fabs(a.x) + std::fabs(ux));
  const double cy_error = uy_error + 4 * eps * (std::fabs(a.y) + std::fabs(uy));
  const double reach_x = r_hi + cx_error, reach_y = r_hi + cy_error;

  double min_x = std::min(a.x, b.x), max_x = std::max(a.x, b.x);
  double min_y = std::min(a.y, b.y), max_y = std::max(a.y, b.y);
  // An extreme point of the circle bounds the region only if it lies on the left arc; include it
  // unless it is clearly right of a->b (tolerance covers the centre and radius errors).
  const double tolerance = (std::fabs(dx) + std::fabs(dy)) * (ux_error + uy_error + (r_hi - r)) * 4 +
                           16 * eps * (std::fabs(dx) + std::fabs(dy)) * (std::fabs(ux) + std::fabs(uy) + r);
  const auto on_left = [&](double ox, double oy) { return dx * oy - dy * ox >= -tolerance; };
  if (on_left(ux + r, uy)) max_x = std::max(max_x, cx + reach_x);
  if (on_left(ux - r, uy)) min_x = std::min(min_x, cx - reach_x);
  if (on_left(ux, uy + r)) max_y = std::max(max_y, cy + reach_y);
  if (on_left(ux, uy - r)) min_y = std::min(min_y, cy - reach_y);
  return {min_x, min_y, max_x, max_y,
          {tree_.quantise_x(min_x), tree_.quantise_y(min_y), tree_.quantise_x(max_x), tree_.quantise_y(max_y)},
          cx, cy, std::max(reach_x, reach_y)};
}

bool ApexSearch::outside_circle(const QuantBox& box, const CircleRegion& region) const {
  // Thin caps over long chords (near-collinear sites) have huge circles whose bounding boxes
  // prune nothing; the distance from the centre to the box does.
  if (region.reach < 0) return false;
  const double q = tree_.quantum();
  const double x_lo = tree_.real_x(static_cast<double>(box.x0)) - q;
  const double x_hi = tree_.real_x(static_cast<double>(box.x1) + 1) + q;
  const double y_lo = tree_.real_y(static_cast<double>(box.y0)) - q;
  const double y_hi = tree_.real_y(static_cast<double>(box.y1) + 1) + q;
  const double dx = std::max({x_lo - region.cx, 0.0, region.cx - x_hi});
  const double dy = std::max({y_lo - region.cy, 0.0, region.cy - y_hi});
  return dx * dx + dy * dy > region.reach * region.reach * (1 + 1e-9);
}

void ApexSearch::start_search(std::int32_t ia, std::int32_t ib) {
  Query& q = query_;
  q.ia = ia;
  q.ib = ib;
  q.a = sites_.points[ia];
  q.b = sites_.points[ib];
  q.dx = q.b.x - q.a.x;
  q.dy = q.b.y - q.a.y;
  q.qmx = tree_.quantise_x(0.5 * q.a.x + 0.5 * q.b.x);
  q.qmy = tree_.quantise_y(0.5 * q.a.y + 0.5 * q.b.y);
  q.edge = exact::apex_edge(q.a.x, q.a.y, q.b.x, q.b.y);
  constexpr double inf = std::numeric_limits<double>::infinity();
  best_.site = -1;
  best_.point = {};
  best_.lambda = 0;
  best_.error = inf;
  best_.lift = {};
  best_.region = {-inf, -inf, inf, inf, full_domain, 0, 0, -1};
  visited_ = {1, 1, 0, 0};
  has_visited_ = false;
  big_buckets_.clear();
}

std::int32_t ApexSearch::apex_search(std::int32_t ia, std::int32_t ib) {
  start_search(ia, ib);
  const Query& q = query_;
  // The region holds a and b, |ab|/2 from the midpoint, and for a well-shaped triangle its apex
  // lies about 0.9 |ab| away: a square of half-size |ab| usually settles it in one round.
  const double length = std::sqrt(q.dx * q.dx + q.dy * q.dy) / tree_.quantum();
  std::uint64_t half = std::max<std::uint64_t>(std::uint64_t{1} << tree_.cell_shift(),
                                               static_cast<std::uint64_t>(std::min(length, 4e9)) + 1);
  // One round visits every bucket that meets `square` but not the previous round's square.
  // Pruning by the best circle is safe for good: a better candidate only shrinks the region.
  while (true) {
    const QuantBox square = square_around(q.qmx, q.qmy, half);
    scan_box(square);
    if (best_.site >= 0 && square.contains(best_.region.quant)) return best_.site;
    if (square.contains(full_domain)) return best_.site;
    visited_ = square;
    has_visited_ = true;
    half *= 2;
  }
}

void ApexSearch::scan_box(const QuantBox& square) {
  constexpr std::uint32_t max_cells_per_side = 5;
  const int shift = tree_.cell_shift();
  const std::uint32_t i0 = square.x0 >> shift, i1 = square.x1 >> shift;
  const std::uint32_t j0 = square.y0 >> shift, j1 = square.y1 >> shift;
  if (i1 - i0 >= max_cells_per_side || j1 - j0 >= max_cells_per_side) {
    descend(0, square);
    return;
  }
  // Enter the tree at the grid's cells, the midpoint's first: skips the top levels for small
  // squares. Then, row by row, only cells that can still meet the circle region (it shrinks
  // as the search goes).
  const std::uint32_t ci = query_.qmx >> shift, cj = query_.qmy >> shift;
  descend(tree_.cell_node(static_cast<int>(ci), static_cast<int>(cj)), square);
  const QuantBox& region = best_.region.quant;
  for (std::uint32_t j = std::max(j0, region.y0 >> shift); j <= std::min(j1, region.y1 >> shift); ++j) {
    for (std::uint32_t i = std::max(i0, region.x0 >> shift); i <= std::min(i1, region.x1 >> shift); ++i) {
      if (i != ci || j != cj) descend(tree_.cell_node(static_cast<int>(i), static_cast<int>(j)), square);
    }
  }
}

void ApexSearch::descend(std::int32_t root, const QuantBox& square) {
  const auto& nodes = tree_.nodes();
  {  // most cells are a single bucket: no stack for them
    const BucketTree::Node node = nodes[root];
    if (node.begin == node.end) return;
    const QuantBox box = tree_.search_box(root);
    if (!box.intersects(square) || !box.intersects(best_.region.quant)) return;
    if (node.first_child == -1) {
      visit_bucket(root, node, box);
      return;
    }
  }
  stack_.clear();
  stack_.push_back(root);
  while (!stack_.empty()) {
    const std::int32_t index = stack_.back();
    const BucketTree::Node node = nodes[index];  // a copy: an on-demand tree grows below
    stack_.pop_back();
    if (node.begin == node.end) continue;
    const QuantBox box = tree_.search_box(index);
    if (!box.intersects(square) || !box.intersects(best_.region.quant)) continue;
    if (has_visited_ && visited_.contains(box)) continue;
    if (node.first_child == -1) {
      visit_bucket(index, node, box);
      continue;
    }
    if (outside_circle(box, best_.region) || entirely_right(box, query_.a, query_.b)) continue;
    if (best_.site >= 0 && outside_lifted_circle(box, query_.a, best_.lift)) continue;
    // Children nearest the midpoint last, so they are popped first.
    const std::int32_t first = tree_.children(index);
    const std::uint32_t mid = node.size / 2;
    const int near = (query_.qmx >= node.x0 + mid ? 1 : 0) | (query_.qmy >= node.y0 + mid ? 2 : 0);
    for (int k = 3; k >= 0; --k) stack_.push_back(first + (near ^ k));
  }
}

// A bucket is scanned unless it met an earlier round's square, or was scanned already this
// round (a bucket spanning several cells is reached from each of them).
void ApexSearch::visit_bucket(std::int32_t index, const BucketTree::Node& node, const QuantBox& box) {
  if (has_visited_ && box.intersects(visited_)) return;
  if (node.size > (1u << tree_.cell_shift())) {
    if (std::find(big_buckets_.begin(), big_buckets_.end(), index) != big_buckets_.end()) return;
    big_buckets_.push_back(index);
  }
  if (scan_bucket(node)) update_circle_region();
}

bool ApexSearch::scan_bucket(const BucketTree::Node& node) {
  const auto& points = sites_.points;
  // The region changes only after the bucket (update_circle_region): its box, read once.
  const double x0 = best_.region.x0, y0 = best_.region.y0, x1 = best_.region.x1, y1 = best_.region.y1;
  bool improved = false;
  for (std::int32_t i = node.begin; i < node.end; ++i) {
    const Point2& e = points[i];
    if (e.x < x0 || e.x > x1 || e.y < y0 || e.y > y1) continue;
    if (i == query_.ia || i == query_.ib) continue;
    ++candidates_tested_;
    if (improves(i, e)) improved = true;
  }
  return improved;
}

bool ApexSearch::improves(std::int32_t i, const Point2& e) {
  // Candidates are ranked by λ: circle(a, b, p) has its centre at m + λ (-dy, dx), and p lies
  // inside circle(a, b, c) exactly when λ(p) < λ(c). λ and its forward error bound cost a few
  // flops; only comparisons the bound cannot separate are decided exactly.
  const Point2& a = query_.a;
  const Point2& b = query_.b;
  const double dx = query_.dx, dy = query_.dy;
  constexpr double inf = std::numeric_limits<double>::infinity();
  const double pax = e.x - a.x, pay = e.y - a.y, pbx = e.x - b.x, pby = e.y - b.y;
  const double cross = dx * pay - dy * pax;
  const double cross_error = 5 * eps * (std::fabs(dx * pay) + std::fabs(dy * pax));
  if (cross < -cross_error) return false;  // clearly right of a->b
  const Point2 p{e.x, e.y};
  double lambda = 0, error = inf;
  // Above 1e-280 no product can have lost bits to underflow beyond the bounds' slack.
  if (cross > cross_error && cross > 1e-280 && cross_error < inf) {
    const double dot = pax * pbx + pay * pby;
    const double dot_error = 5 * eps * (std::fabs(pax * pbx) + std::fabs(pay * pby)) + 1e-300;
    lambda = dot / (2 * cross);
    error = (dot_error + 2 * std::fabs(lambda) * cross_error) / (2 * (cross - cross_error)) + 4 * eps * std::fabs(lambda);
    if (!std::isfinite(error)) error = inf;
  } else if (orient2d(a, b, p) <= 0) {
    return false;
  }
  int better;  // 1, 0, or exact::uncertain
  if (best_.site < 0) {
    better = 1;
  } else if (error < inf && best_.error < inf && lambda + error < best_.lambda - best_.error) {
    better = 1;
  } else if (error < inf && best_.error < inf && lambda - error > best_.lambda + best_.error) {
    better = 0;
  } else {
    better = exact::uncertain;
  }
  if (better == exact::uncertain) better = decide_exactly(p) ? 1 : 0;
  if (!better) return false;
  best_.site = i;
  best_.point = p;
  best_.lambda = lambda;
  best_.error = error;
  return true;
}

bool ApexSearch::decide_exactly(const Point2& p) const {
  return incircle_perturbed(query_.a, query_.b, best_.point, p) > 0;
}

void ApexSearch::update_circle_region() {
  const Query& q = query_;
  best_.lift = exact::apex_lift(q.edge, exact::apex_point(q.edge, best_.point.x, best_.point.y));
  // λ's centre only where its relative error is below 1e-9 (see circle_region).
  if (best_.error < 1e-9 * (1 + std::fabs(best_.lambda))) {
    const double lambda = best_.lambda, dx = q.dx, dy = q.dy;
    const double ux = 0.5 * dx - lambda * dy, uy = 0.5 * dy + lambda * dx;
    const double ux_error = best_.error * std::fabs(dy) + 8 * eps * (std::fabs(dx) + std::fabs(lambda * dy));
    const double uy_error = best_.error * std::fabs(dx) + 8 * eps * (std::fabs(dy) + std::fabs(lambda * dx));
    best_.region = circle_region_around(q.a, q.b, ux, uy, ux_error, uy_error);
  } else {
    best_.region = circle_region(q.a, q.b, best_.point);
  }
}

std::int32_t ApexSearch::nearest_site(std::int32_t s) { return nearest(sites_.points[s], s); }

std::int32_t ApexSearch::nearest(const Point2& q, std::int32_t exclude) {
  const auto& nodes = tree_.nodes();
  const auto& points = sites_.points;
  if (points.empty()) return -1;
  const std::uint32_t qx = tree_.quantise_x(q.x), qy = tree_.quantise_y(q.y);
  std::uint64_t half = tree_.bucket_size_at(qx, qy);
  std::int32_t best = -1;
  Point2 best_point{};
  QuantBox best_box = full_domain;
  QuantBox visited{};
  bool has_visited = false;
  while (true) {
    const QuantBox square = square_around(qx, qy, half);
    stack_.clear();
    stack_.push_back(0);
    while (!stack_.empty()) {
      const std::int32_t index = stack_.back();
      const BucketTree::Node node = nodes[index];  // a copy: an on-demand tree grows below
      stack_.pop_back();
      if (node.begin == node.end) continue;
      const QuantBox box = node.box();
      if (!box.intersects(square) || !box.intersects(best_box)) continue;
      if (has_visited && visited.contains(box)) continue;
      if (node.first_child != -1) {
        const std::int32_t first = tree_.children(index);
        for (int k = 0; k < 4; ++k) stack_.push_back(first + k);
        continue;
      }
      if (has_visited && box.intersects(visited)) continue;
      for (std::int32_t i = node.begin; i < node.end; ++i) {
        if (i == exclude) continue;
        const Point2& p = points[i];
        if (best < 0 || compare_squared_distance(q, p, best_point) < 0) {
          best = i;
          best_point = p;
          const double r = std::hypot(p.x - q.x, p.y - q.y) * (1 + 1e-9) + 4 * tree_.quantum();
          best_box = {tree_.quantise_x(q.x - r), tree_.quantise_y(q.y - r), tree_.quantise_x(q.x + r),
                      tree_.quantise_y(q.y + r)};
        }
      }
    }
    if (best >= 0 && square.contains(best_box)) return best;
    if (square.contains(full_domain)) return best;
    visited = square;
    has_visited = true;
    half *= 2;
  }
}

}  // namespace expanse::detail
