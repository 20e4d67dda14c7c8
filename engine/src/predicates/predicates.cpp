// The predicates' slow paths: everything the inline filter in predicates.hpp cannot decide.
#include "predicates/predicates.hpp"

#include <algorithm>
#include <array>
#include <initializer_list>

#include <gmpxx.h>

namespace expanse::detail {
namespace {

bool all_in_safe_range(std::initializer_list<const Point2*> points) {
  for (const Point2* p : points)
    if (!exact::in_safe_range(p->x) || !exact::in_safe_range(p->y)) return false;
  return true;
}

// Rationals: the last resort for coordinates whose powers leave the double exponent range.
// mpq_class(double) converts exactly (every finite double is a dyadic rational).
int sign_of(const mpq_class& value) { return sgn(value); }

int orient2d_rational(const Point2& a, const Point2& b, const Point2& c) {
  const mpq_class acx = mpq_class(a.x) - mpq_class(c.x), bcy = mpq_class(b.y) - mpq_class(c.y);
  const mpq_class acy = mpq_class(a.y) - mpq_class(c.y), bcx = mpq_class(b.x) - mpq_class(c.x);
  return sign_of(acx * bcy - acy * bcx);
}

int incircle_rational(const Point2& a, const Point2& b, const Point2& c, const Point2& d) {
  const mpq_class dx(d.x), dy(d.y);
  const mpq_class adx = mpq_class(a.x) - dx, ady = mpq_class(a.y) - dy;
  const mpq_class bdx = mpq_class(b.x) - dx, bdy = mpq_class(b.y) - dy;
  const mpq_class cdx = mpq_class(c.x) - dx, cdy = mpq_class(c.y) - dy;
  const mpq_class alift = adx * adx + ady * ady;
  const mpq_class blift = bdx * bdx + bdy * bdy;
  const mpq_class clift = cdx * cdx + cdy * cdy;
  return sign_of(alift * (bdx * cdy - cdx * bdy) + blift * (cdx * ady - adx * cdy) +
                 clift * (adx * bdy - bdx * ady));
}

bool lexicographically_less(const Point2& p, const Point2& q) {
  return p.x < q.x || (p.x == q.x && p.y < q.y);
}

}  // namespace

int orient2d_exact(const Point2& a, const Point2& b, const Point2& c) {
  if (!all_in_safe_range({&a, &b, &c})) return orient2d_rational(a, b, c);
  const int certified = exact::orient2d_certified(a.x, a.y, b.x, b.y, c.x, c.y);
  if (certified != exact::uncertain) return certified;
  return exact::orient2d_expansion(a.x, a.y, b.x, b.y, c.x, c.y);
}

int incircle_exact(const Point2& a, const Point2& b, const Point2& c, const Point2& d) {
  if (!all_in_safe_range({&a, &b, &c, &d})) return incircle_rational(a, b, c, d);
  const int certified = exact::incircle_certified(a.x, a.y, b.x, b.y, c.x, c.y, d.x, d.y);
  if (certified != exact::uncertain) return certified;
  const int small = exact::incircle_exact_differences(a.x, a.y, b.x, b.y, c.x, c.y, d.x, d.y);
  if (small != exact::uncertain) return small;
  return exact::incircle_expansion(a.x, a.y, b.x, b.y, c.x, c.y, d.x, d.y);
}

int perturbed_tie_break(const Point2& p0, const Point2& p1, const Point2& p2, const Point2& p) {
  // CGAL perturbs the lifted coordinate of each point by an amount that shrinks with its
  // lexicographic rank, largest point most. Walking from the largest point down, the first
  // one whose perturbation changes the sign decides it.
  std::array<const Point2*, 4> points{&p0, &p1, &p2, &p};
  std::sort(points.begin(), points.end(),
            [](const Point2* u, const Point2* v) { return lexicographically_less(*v, *u); });
  // Two steps always suffice for CCW (p0, p1, p2) (Devillers & Teillaud); CGAL stops there.
  for (int rank = 0; rank < 2; ++rank) {
    const Point2* largest = points[rank];
    if (largest == &p) return -1;
    int orientation = 0;
    if (largest == &p2)
      orientation = orient2d(p0, p1, p);
    else if (largest == &p1)
      orientation = orient2d(p0, p, p2);
    else
      orientation = orient2d(p, p1, p2);
    if (orientation != 0) return orientation;
  }
  return -1;  // CGAL's answer when both steps are degenerate (unreachable for valid input).
}

int incircle_perturbed(const Point2& p0, const Point2& p1, const Point2& p2, const Point2& p) {
  const int sign = incircle(p0, p1, p2, p);
  if (sign != 0) return sign;
  return perturbed_tie_break(p0, p1, p2, p);
}

}  // namespace expanse::detail
