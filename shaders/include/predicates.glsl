// Device predicates: the host's error-bounded filters and exactness certificates
// (engine/src/predicates/exact_arith.hpp), transcribed in the same operation order. There is no
// device expansion arithmetic: what neither can decide returns uncertain and the caller defers
// the expansion to the exact CPU seam stage.
#ifndef EXPANSE_PREDICATES_GLSL
#define EXPANSE_PREDICATES_GLSL

#include "eft.glsl"

#include "host_device.h"
const double EPS = 1.1102230246251565e-16lf;  // 2^-53
const double ORIENT_BOUND = (3.0lf + 16.0lf * EPS) * EPS;
const double INCIRCLE_BOUND = (10.0lf + 96.0lf * EPS) * EPS;
// The host uses 2^-1069 to cover underflowed products. The backend only sends sites whose
// nonzero coordinates are at least 2^-200 in magnitude (else it defers everything), so no
// value formed here is subnormal and a device that flushes subnormals cannot be fooled; a
// normal 2^-1000 keeps the bound at least as large as the host's without a subnormal literal.
const double UNDERFLOW_SLACK = 9.332636185032189e-302lf;

int orient2d_filter(dvec2 a, dvec2 b, dvec2 c) {
  precise double left = (a.x - c.x) * (b.y - c.y);
  precise double right = (a.y - c.y) * (b.x - c.x);
  precise double det = left - right;
  precise double permanent = mag(left) + mag(right);
  precise double bound = ORIENT_BOUND * permanent + UNDERFLOW_SLACK;
  if (det > bound) return 1;
  if (-det > bound) return -1;
  return uncertain;
}

int incircle_filter(dvec2 a, dvec2 b, dvec2 c, dvec2 d) {
  precise double adx = a.x - d.x, ady = a.y - d.y;
  precise double bdx = b.x - d.x, bdy = b.y - d.y;
  precise double cdx = c.x - d.x, cdy = c.y - d.y;
  precise double bdxcdy = bdx * cdy, cdxbdy = cdx * bdy;
  precise double cdxady = cdx * ady, adxcdy = adx * cdy;
  precise double adxbdy = adx * bdy, bdxady = bdx * ady;
  precise double alift = adx * adx + ady * ady;
  precise double blift = bdx * bdx + bdy * bdy;
  precise double clift = cdx * cdx + cdy * cdy;
  precise double det = (alift * (bdxcdy - cdxbdy) + blift * (cdxady - adxcdy)) +
                       clift * (adxbdy - bdxady);
  precise double a_cross = mag(bdxcdy) + mag(cdxbdy);
  precise double b_cross = mag(cdxady) + mag(adxcdy);
  precise double c_cross = mag(adxbdy) + mag(bdxady);
  precise double permanent = (a_cross * alift + b_cross * blift) + c_cross * clift;
  precise double losses = ((alift + blift) + (clift + a_cross)) + ((b_cross + c_cross) + 1.0lf);
  precise double bound = INCIRCLE_BOUND * permanent + UNDERFLOW_SLACK * losses;
  if (det > bound) return 1;
  if (-det > bound) return -1;
  return uncertain;
}

// The apex filters in the edge's frame (engine/src/predicates/apex_filter.hpp, where their
// error bounds are argued), transcribed operation for operation and with the host's underflow
// rule (a bound widened by 2^-98, trusted only where the losses fit in it), so that both
// decide the same signs. Precondition: |coordinates| < 1, as the scaled sites.
const double WIDENING = 3.1554436208840472e-30lf;  // 2^-98
const double ORIENT_FILTER_BOUND = ORIENT_BOUND + WIDENING;
const double INCIRCLE_FILTER_BOUND = INCIRCLE_BOUND + WIDENING;
// The apex filters' factors, rounded up as apex_filter.hpp's (0x1.80001p-52, 0x1.40001p-50).
const double APEX_ORIENT_BOUND = 3.330671191457838e-16lf;
const double APEX_INCIRCLE_BOUND = 1.1102238716581038e-15lf;

struct ApexLift {
  double k, vx, vy, k_perm, vx_perm, vy_perm;
};

int sign_beyond(double det, double bound) {
  return det > bound ? 1 : (-det > bound ? -1 : uncertain);
}

// P = p - a and |P|^2.
dvec3 apex_point(dvec2 a, dvec2 p) {
  precise dvec2 q = p - a;
  precise double d2 = q.x * q.x + q.y * q.y;
  return dvec3(q, d2);
}

// apex_point where |p - a|^2 is known (the best candidate's, kept as it was formed): the same
// value, three operations fewer a candidate.
dvec3 apex_point_with(dvec2 a, dvec2 p, double d2) {
  precise dvec2 q = p - a;
  return dvec3(q, d2);
}

// p's lift against the edge a->b, given B = b - a and |B|^2.
ApexLift apex_lift(dvec2 edge, double b2, dvec3 p) {
  precise double k_left = edge.x * p.y, k_right = edge.y * p.x;
  precise double vx_left = b2 * p.y, vx_right = edge.y * p.z;
  precise double vy_left = edge.x * p.z, vy_right = b2 * p.x;
  precise double k = k_left - k_right;
  precise double vx = vx_left - vx_right;
  precise double vy = vy_left - vy_right;
  precise double k_perm = mag(k_left) + mag(k_right);
  precise double vx_perm = mag(vx_left) + mag(vx_right);
  precise double vy_perm = mag(vy_left) + mag(vy_right);
  return ApexLift(k, vx, vy, k_perm, vx_perm, vy_perm);
}

int apex_orient_filter(ApexLift p) {
  precise double bound = APEX_ORIENT_BOUND * p.k_perm;
  return p.k_perm >= 6.26302612502804e-294lf ? sign_beyond(p.k, bound) : uncertain;  // 2^-974
}

// incircle(a, b, c, p) from c's lift as apex_incircle_filter forms it: exact on small integer
// lattices (engine/src/predicates/exact_lattice.hpp).
double apex_incircle_value(ApexLift c, dvec3 p) {
  precise double det = (p.x * c.vx + p.y * c.vy) - p.z * c.k;
  return det;
}

// Sign of incircle(a, b, c, p), c the candidate whose lift is `c`.
int apex_incircle_filter(ApexLift c, dvec3 p) {
  precise double ax = mag(p.x), ay = mag(p.y);
  precise double det = (p.x * c.vx + p.y * c.vy) - p.z * c.k;
  precise double permanent = (ax * c.vx_perm + ay * c.vy_perm) + p.z * c.k_perm;
  precise double bound = APEX_INCIRCLE_BOUND * permanent;
  // Underflow losses under 21 * 2^-969 for |coordinates| < 1 (apex_filter.hpp).
  bool trusted = permanent >= 6.413338752028713e-291lf;  // 2^-964
  return trusted ? sign_beyond(det, bound) : uncertain;
}

bool in_safe_range(double v) {
  double m = mag(v);
  // [2^-200, 2^200]
  return v == 0.0lf || (m >= 6.223015277861142e-61lf && m <= 1.6069380442589903e60lf);
}

bool safe2(dvec2 p) { return in_safe_range(p.x) && in_safe_range(p.y); }

int orient2d_certified(dvec2 a, dvec2 b, dvec2 c) {
  if (!(safe2(a) && safe2(b) && safe2(c))) return uncertain;
  double e0, e1, e2, e3, e4, e5, e6;
  precise double acx = two_diff(a.x, c.x, e0);
  precise double bcy = two_diff(b.y, c.y, e1);
  precise double acy = two_diff(a.y, c.y, e2);
  precise double bcx = two_diff(b.x, c.x, e3);
  precise double left = two_product(acx, bcy, e4);
  precise double right = two_product(acy, bcx, e5);
  precise double det = two_diff(left, right, e6);
  bool exact = e0 == 0.0lf && e1 == 0.0lf && e2 == 0.0lf && e3 == 0.0lf && e4 == 0.0lf &&
               e5 == 0.0lf && e6 == 0.0lf;
  if (!exact) return uncertain;
  return int(det > 0.0lf) - int(det < 0.0lf);
}

// Certified operations accumulate "every remainder was zero" in `ok`.
double cdiff(double p, double q, inout bool ok) {
  double e;
  precise double r = two_diff(p, q, e);
  ok = ok && e == 0.0lf;
  return r;
}
double csum(double p, double q, inout bool ok) {
  double e;
  precise double r = two_sum(p, q, e);
  ok = ok && e == 0.0lf;
  return r;
}
double cprod(double p, double q, inout bool ok) {
  double e;
  precise double r = two_product(p, q, e);
  ok = ok && e == 0.0lf;
  return r;
}

// Squared distance, certified exact (ok stays true) or not.
double squared_distance_certified(dvec2 p, dvec2 q, inout bool ok) {
  precise double dx = cdiff(p.x, q.x, ok);
  precise double dy = cdiff(p.y, q.y, ok);
  return csum(cprod(dx, dx, ok), cprod(dy, dy, ok), ok);
}

int incircle_certified(dvec2 a, dvec2 b, dvec2 c, dvec2 d) {
  if (!(safe2(a) && safe2(b) && safe2(c) && safe2(d))) return uncertain;
  bool ok = true;
  precise double adx = cdiff(a.x, d.x, ok), ady = cdiff(a.y, d.y, ok);
  precise double bdx = cdiff(b.x, d.x, ok), bdy = cdiff(b.y, d.y, ok);
  precise double cdx = cdiff(c.x, d.x, ok), cdy = cdiff(c.y, d.y, ok);
  precise double alift = csum(cprod(adx, adx, ok), cprod(ady, ady, ok), ok);
  precise double blift = csum(cprod(bdx, bdx, ok), cprod(bdy, bdy, ok), ok);
  precise double clift = csum(cprod(cdx, cdx, ok), cprod(cdy, cdy, ok), ok);
  precise double a_term = cprod(alift, cdiff(cprod(bdx, cdy, ok), cprod(cdx, bdy, ok), ok), ok);
  precise double b_term = cprod(blift, cdiff(cprod(cdx, ady, ok), cprod(adx, cdy, ok), ok), ok);
  precise double c_term = cprod(clift, cdiff(cprod(adx, bdy, ok), cprod(bdx, ady, ok), ok), ok);
  precise double det = csum(csum(a_term, b_term, ok), c_term, ok);
  if (!ok) return uncertain;
  return int(det > 0.0lf) - int(det < 0.0lf);
}

// Exact signs of small sums of exact products, as an expansion: h[0 .. len) in increasing
// magnitude, non-overlapping, no zeros. EXPANSION_GROW(x) adds x in place (Shewchuk's
// GROW-EXPANSION-ZEROELIM), setting `fits` false when the result would not fit. A macro, not a
// function: GLSL copies an `inout` array in and out on every call (on lavapipe that copying was
// most of the time).
const int EXACT_TERMS = 40;  // a non-overlapping expansion within the safe range needs < 40
#define EXPANSION_GROW(x)                                 \
  {                                                       \
    precise double q_ = (x);                              \
    int out_ = 0;                                         \
    for (int i_ = 0; i_ < len; ++i_) {                    \
      double e_;                                          \
      precise double sum_ = two_sum(q_, h[i_], e_);       \
      q_ = sum_;                                          \
      if (e_ != 0.0lf) h[out_++] = e_;                    \
    }                                                     \
    if (q_ != 0.0lf || out_ == 0) {                       \
      if (out_ == EXACT_TERMS) fits = false;              \
      else h[out_++] = q_;                                \
    }                                                     \
    len = out_;                                           \
  }

// The sign of the expansion h[0 .. len): that of its largest term.
int expansion_sign(double top) { return int(top > 0.0lf) - int(top < 0.0lf); }

// incircle's exact sign where the six coordinate differences against d are exact, else
// uncertain: exact_arith.hpp's incircle_exact_differences_grown, the determinant's 96 exact
// products grown term by term into one expansion of at most EXACT_TERMS doubles. Decimal grids
// and other nearly cocircular float inputs: nearby sites of one magnitude have exact differences
// (Sterbenz).
int incircle_exact_differences(dvec2 a, dvec2 b, dvec2 c, dvec2 d) {
  if (!(safe2(a) && safe2(b) && safe2(c) && safe2(d))) return uncertain;
  bool ok = true;
  precise dvec2 ad = dvec2(cdiff(a.x, d.x, ok), cdiff(a.y, d.y, ok));
  precise dvec2 bd = dvec2(cdiff(b.x, d.x, ok), cdiff(b.y, d.y, ok));
  precise dvec2 cd = dvec2(cdiff(c.x, d.x, ok), cdiff(c.y, d.y, ok));
  if (!ok) return uncertain;
  double h[EXACT_TERMS];
  int len = 0;
  bool fits = true;
  // lift(u) * (v.x w.y - w.x v.y) for (u, v, w) = (a, b, c), (b, c, a), (c, a, b).
  for (int t = 0; t < 3; ++t) {
    dvec2 u = t == 0 ? ad : (t == 1 ? bd : cd);
    dvec2 v = t == 0 ? bd : (t == 1 ? cd : ad);
    dvec2 w = t == 0 ? cd : (t == 1 ? ad : bd);
    double lift[4], minor[4];
    lift[0] = two_product(u.x, u.x, lift[1]);
    lift[2] = two_product(u.y, u.y, lift[3]);
    minor[0] = two_product(v.x, w.y, minor[1]);
    double m2, m3;
    m2 = two_product(w.x, v.y, m3);
    minor[2] = -m2;
    minor[3] = -m3;
    for (int k = 0; k < 16; ++k) {
      double e;
      precise double p = two_product(lift[k >> 2], minor[k & 3], e);
      EXPANSION_GROW(e)
      EXPANSION_GROW(p)
    }
  }
  return fits ? expansion_sign(h[len - 1]) : uncertain;
}

// orient2d's exact sign where the four coordinate differences are exact, else uncertain.
int orient2d_exact_differences(dvec2 a, dvec2 b, dvec2 c) {
  if (!(safe2(a) && safe2(b) && safe2(c))) return uncertain;
  bool ok = true;
  precise double acx = cdiff(a.x, c.x, ok), bcy = cdiff(b.y, c.y, ok);
  precise double acy = cdiff(a.y, c.y, ok), bcx = cdiff(b.x, c.x, ok);
  if (!ok) return uncertain;
  double h[EXACT_TERMS];
  int len = 0;
  bool fits = true;
  double e1, e2;
  precise double left = two_product(acx, bcy, e1);
  precise double right = two_product(acy, bcx, e2);
  EXPANSION_GROW(e1)
  EXPANSION_GROW(left)
  EXPANSION_GROW(-e2)
  EXPANSION_GROW(-right)
  return fits ? expansion_sign(h[len - 1]) : uncertain;
}

// Sign of |p - s|^2 - |q - s|^2 where the four coordinate differences are exact, else uncertain
// (the nearest-neighbour comparison of nearly cocircular float inputs).
int compare_distance_exact_differences(dvec2 s, dvec2 p, dvec2 q) {
  if (!(safe2(s) && safe2(p) && safe2(q))) return uncertain;
  bool ok = true;
  precise dvec2 ps = dvec2(cdiff(p.x, s.x, ok), cdiff(p.y, s.y, ok));
  precise dvec2 qs = dvec2(cdiff(q.x, s.x, ok), cdiff(q.y, s.y, ok));
  if (!ok) return uncertain;
  double h[EXACT_TERMS];
  int len = 0;
  bool fits = true;
  for (int k = 0; k < 4; ++k) {
    double v = k == 0 ? ps.x : (k == 1 ? ps.y : (k == 2 ? qs.x : qs.y));
    double e;
    precise double square = two_product(v, v, e);
    double sign = k < 2 ? 1.0lf : -1.0lf;
    EXPANSION_GROW(sign * e)
    EXPANSION_GROW(sign * square)
  }
  return fits ? expansion_sign(h[len - 1]) : uncertain;
}

// Filter, then certificate; uncertain only when both give up.
int orient2d_device(dvec2 a, dvec2 b, dvec2 c) {
  int s = orient2d_filter(a, b, c);
  if (s != uncertain) return s;
  return orient2d_certified(a, b, c);
}

int incircle_device(dvec2 a, dvec2 b, dvec2 c, dvec2 d) {
  int s = incircle_filter(a, b, c, d);
  if (s != uncertain) return s;
  return incircle_certified(a, b, c, d);
}

bool lex_less(dvec2 p, dvec2 q) { return p.x < q.x || (p.x == q.x && p.y < q.y); }

// incircle_perturbed_device's answer where p0, p1, p2, q are exactly cocircular: CGAL's
// symbolic perturbation walks the four points from the lexicographically largest down (two
// steps suffice). Index 3 is q.
// With `differences`, orientations the certificate cannot decide are tried from exact
// differences too (orient2d_exact_differences).
int cocircular_perturbed_device(dvec2 p0, dvec2 p1, dvec2 p2, dvec2 q, bool differences) {
  dvec2 pts[4] = dvec2[4](p0, p1, p2, q);
  int order[4] = int[4](0, 1, 2, 3);
  for (int i = 1; i < 4; ++i) {  // insertion sort, ascending
    int k = order[i];
    int j = i - 1;
    while (j >= 0 && lex_less(pts[k], pts[order[j]])) {
      order[j + 1] = order[j];
      --j;
    }
    order[j + 1] = k;
  }
  for (int i = 3; i > 1; --i) {
    int w = order[i];
    if (w == 3) return -1;
    int o;
    dvec2 u = w == 2 ? p0 : (w == 1 ? p0 : q), v = w == 2 ? p1 : (w == 1 ? q : p1), x = w == 2 ? q : p2;
    o = orient2d_device(u, v, x);
    if (o == uncertain && differences) o = orient2d_exact_differences(u, v, x);
    if (o == uncertain) return uncertain;
    if (o != 0) return o;
  }
  return uncertain;  // unreachable for distinct sites and a CCW triangle
}

// cocircular_perturbed_device on a small integer lattice (engine/src/predicates/exact_lattice.hpp),
// where orientations are exact in plain doubles: the same walk without loops or branches (the
// points' lexicographic ranks from their six comparisons, the three orientations it may need),
// so that lavapipe's masked lanes pay little for it in the candidate loop.
int cocircular_perturbed_lattice(dvec2 p0, dvec2 p1, dvec2 p2, dvec2 q) {
  bool l01 = lex_less(p0, p1), l02 = lex_less(p0, p2), l03 = lex_less(p0, q);
  bool l12 = lex_less(p1, p2), l13 = lex_less(p1, q), l23 = lex_less(p2, q);
  int r1 = int(l01) + int(!l12) + int(!l13);  // how many of the others precede p1
  int r2 = int(l02) + int(l12) + int(!l23);
  int r3 = int(l03) + int(l13) + int(l23);
  precise double d0 = (q.x - p2.x) * (p1.y - p2.y) - (q.y - p2.y) * (p1.x - p2.x);    // orient(q, p1, p2)
  precise double d1 = (p0.x - p2.x) * (q.y - p2.y) - (p0.y - p2.y) * (q.x - p2.x);    // orient(p0, q, p2)
  precise double d2 = (p0.x - q.x) * (p1.y - q.y) - (p0.y - q.y) * (p1.x - q.x);      // orient(p0, p1, q)
  int o0 = int(sign(d0)), o1 = int(sign(d1)), o2 = int(sign(d2));
  int first = r2 == 3 ? o2 : (r1 == 3 ? o1 : o0);    // the largest point's orientation
  int second = r2 == 2 ? o2 : (r1 == 2 ? o1 : o0);   // the next one's
  return r3 == 3 ? -1 : (first != 0 ? first : (r3 == 2 ? -1 : (second != 0 ? second : uncertain)));
}

// CGAL's Delaunay_triangulation_2::side_of_oriented_circle(p0, p1, p2, q, perturb = true) for
// CCW (p0, p1, p2) and q distinct from them: +1 inside the perturbed circle, -1 outside, never 0;
// uncertain when an unperturbed sign could not be decided on the device.
int incircle_perturbed_device(dvec2 p0, dvec2 p1, dvec2 p2, dvec2 q) {
  int s = incircle_device(p0, p1, p2, q);
  return s != 0 ? s : cocircular_perturbed_device(p0, p1, p2, q, false);
}

// The same, trying incircle_exact_differences (and orientations from exact differences) where
// filter and certificate give up.
int incircle_perturbed_exact_differences(dvec2 p0, dvec2 p1, dvec2 p2, dvec2 q) {
  int s = incircle_device(p0, p1, p2, q);
  if (s == uncertain) s = incircle_exact_differences(p0, p1, p2, q);
  return s != 0 ? s : cocircular_perturbed_device(p0, p1, p2, q, true);
}

#endif
