#pragma once
// Error-free transformations, fixed-capacity floating-point expansions, and the two cheap
// decision procedures every executor shares: the error-bounded filter and the exactness
// certificate. Host and device compile this same code (EXPANSE_HD), so a sign decided on a GPU
// is the sign the CPU would decide.
//
// Everything here assumes IEEE-754 binary64 with round-to-nearest-even, gradual underflow, and
// NO contraction of a*b+c into fma: an fma computes a*b+c with one rounding, which silently turns
// the error terms below into garbage. Host code builds with -ffp-contract=off; device code goes
// through __dadd_rn/__dsub_rn/__dmul_rn, which nvcc never contracts.

#if defined(__CUDACC__)
#define EXPANSE_HD __host__ __device__
#else
#define EXPANSE_HD
#endif

#if defined(__clang__)
#pragma STDC FP_CONTRACT OFF
#endif

namespace expanse::detail::exact {

// ---- Rounded arithmetic that no compiler may fuse -------------------------------------------

EXPANSE_HD inline double add(double a, double b) {
#if defined(__CUDA_ARCH__)
  return __dadd_rn(a, b);
#else
  return a + b;
#endif
}

EXPANSE_HD inline double sub(double a, double b) {
#if defined(__CUDA_ARCH__)
  return __dsub_rn(a, b);
#else
  return a - b;
#endif
}

EXPANSE_HD inline double mul(double a, double b) {
#if defined(__CUDA_ARCH__)
  return __dmul_rn(a, b);
#else
  return a * b;
#endif
}

/// |a| by clearing the sign bit: a conditional negation would compile to a branch that random
/// signs mispredict, which costs the filters more than all their arithmetic.
EXPANSE_HD inline double magnitude(double a) {
#if defined(__CUDA_ARCH__)
  return fabs(a);
#else
  return __builtin_fabs(a);
#endif
}

// ---- Error-free transformations --------------------------------------------------------------
// Each returns the rounded result and stores in `error` the exact remainder, so that
// result + error equals the exact real value (barring overflow, and for products underflow).

EXPANSE_HD inline double two_sum(double a, double b, double& error) {
  const double sum = add(a, b);
  const double b_part = sub(sum, a);
  const double a_part = sub(sum, b_part);
  error = add(sub(a, a_part), sub(b, b_part));
  return sum;
}

/// Requires |a| >= |b| (or a == 0); three operations instead of six.
EXPANSE_HD inline double fast_two_sum(double a, double b, double& error) {
  const double sum = add(a, b);
  error = sub(b, sub(sum, a));
  return sum;
}

EXPANSE_HD inline double two_diff(double a, double b, double& error) {
  const double diff = sub(a, b);
  const double b_part = sub(a, diff);
  const double a_part = add(diff, b_part);
  error = add(sub(a, a_part), sub(b_part, b));
  return diff;
}

/// Dekker's split: a = high + low, each with at most 26 significant bits, so that products of
/// halves are exact. Overflows for |a| > ~2^996; callers keep magnitudes far below that.
EXPANSE_HD inline void split(double a, double& high, double& low) {
  constexpr double splitter = 134217729.0;  // 2^27 + 1
  const double scaled = mul(splitter, a);
  const double big = sub(scaled, a);
  high = sub(scaled, big);
  low = sub(a, high);
}

EXPANSE_HD inline double two_product(double a, double b, double& error) {
  const double product = mul(a, b);
  double a_high, a_low, b_high, b_low;
  split(a, a_high, a_low);
  split(b, b_high, b_low);
  const double rest1 = sub(product, mul(a_high, b_high));
  const double rest2 = sub(rest1, mul(a_low, b_high));
  const double rest3 = sub(rest2, mul(a_high, b_low));
  error = sub(mul(a_low, b_low), rest3);
  return product;
}

// ---- Expansions -------------------------------------------------------------------------------
// An expansion is a sum of doubles, stored in increasing order of magnitude, pairwise
// non-overlapping, zeros removed. Its sign is the sign of its largest term. Capacities are
// compile-time, so the whole thing lives on the stack (host) or in registers/local memory
// (device).

template <int Capacity>
struct Expansion {
  static constexpr int capacity = Capacity;
  double term[Capacity];
  int size = 0;

  EXPANSE_HD int sign() const {
    if (size == 0) return 0;
    return term[size - 1] > 0.0 ? 1 : -1;
  }
  /// A double close to the value (the rounded sum of the terms, smallest first).
  EXPANSE_HD double approximate() const {
    double total = 0.0;
    for (int i = 0; i < size; ++i) total = add(total, term[i]);
    return total;
  }
};

/// The exact value of a single double.
EXPANSE_HD inline Expansion<1> expansion_of(double a) {
  Expansion<1> e;
  if (a != 0.0) e.term[e.size++] = a;
  return e;
}

/// a - b exactly, as two terms.
EXPANSE_HD inline Expansion<2> exact_difference(double a, double b) {
  Expansion<2> e;
  double error;
  const double diff = two_diff(a, b, error);
  if (error != 0.0) e.term[e.size++] = error;
  if (diff != 0.0) e.term[e.size++] = diff;
  return e;
}

/// a * b exactly, as two terms.
EXPANSE_HD inline Expansion<2> exact_product(double a, double b) {
  Expansion<2> e;
  double error;
  const double product = two_product(a, b, error);
  if (error != 0.0) e.term[e.size++] = error;
  if (product != 0.0) e.term[e.size++] = product;
  return e;
}

/// h = e + f on raw arrays (merge by magnitude, then one pass of two_sum); h may not alias e or
/// f. Returns the number of terms. Inputs must be strongly non-overlapping (true of everything
/// built by these routines under round-to-nearest-even).
EXPANSE_HD inline int sum_terms(const double* e, int e_size, const double* f, int f_size, double* h) {
  if (e_size == 0) {
    for (int i = 0; i < f_size; ++i) h[i] = f[i];
    return f_size;
  }
  if (f_size == 0) {
    for (int i = 0; i < e_size; ++i) h[i] = e[i];
    return e_size;
  }
  int ei = 0, fi = 0, h_size = 0;
  // Take the smaller-magnitude head first, so that every accumulation step sees its operands
  // in the order fast_two_sum needs.
  auto take_smaller = [&]() -> double {
    if (fi >= f_size || (ei < e_size && magnitude(e[ei]) < magnitude(f[fi]))) return e[ei++];
    return f[fi++];
  };
  double running = take_smaller();
  double next = take_smaller();
  double error;
  running = fast_two_sum(next, running, error);
  if (error != 0.0) h[h_size++] = error;
  while (ei < e_size || fi < f_size) {
    next = take_smaller();
    running = two_sum(running, next, error);
    if (error != 0.0) h[h_size++] = error;
  }
  if (running != 0.0 || h_size == 0) h[h_size++] = running;
  if (h_size == 1 && h[0] == 0.0) h_size = 0;
  return h_size;
}

/// h = e * b on raw arrays; h may not alias e. Returns the number of terms.
EXPANSE_HD inline int scale_terms(const double* e, int e_size, double b, double* h) {
  if (e_size == 0 || b == 0.0) return 0;
  double b_high, b_low;
  split(b, b_high, b_low);
  int h_size = 0;
  double error;
  // Same Dekker product as two_product, reusing b's split.
  auto product_with_b = [&](double a, double& product_error) {
    const double product = mul(a, b);
    double a_high, a_low;
    split(a, a_high, a_low);
    const double rest1 = sub(product, mul(a_high, b_high));
    const double rest2 = sub(rest1, mul(a_low, b_high));
    const double rest3 = sub(rest2, mul(a_high, b_low));
    product_error = sub(mul(a_low, b_low), rest3);
    return product;
  };
  double running = product_with_b(e[0], error);
  if (error != 0.0) h[h_size++] = error;
  for (int i = 1; i < e_size; ++i) {
    double product_error;
    const double product = product_with_b(e[i], product_error);
    const double partial = two_sum(running, product_error, error);
    if (error != 0.0) h[h_size++] = error;
    running = fast_two_sum(product, partial, error);
    if (error != 0.0) h[h_size++] = error;
  }
  if (running != 0.0) h[h_size++] = running;
  return h_size;
}

template <int M, int N>
EXPANSE_HD inline Expansion<M + N> operator+(const Expansion<M>& e, const Expansion<N>& f) {
  Expansion<M + N> h;
  h.size = sum_terms(e.term, e.size, f.term, f.size, h.term);
  return h;
}

template <int M>
EXPANSE_HD inline Expansion<M> operator-(const Expansion<M>& e) {
  Expansion<M> h = e;
  for (int i = 0; i < h.size; ++i) h.term[i] = -h.term[i];
  return h;
}

template <int M, int N>
EXPANSE_HD inline Expansion<M + N> operator-(const Expansion<M>& e, const Expansion<N>& f) {
  return e + (-f);
}

template <int M>
EXPANSE_HD inline Expansion<2 * M> scale(const Expansion<M>& e, double b) {
  Expansion<2 * M> h;
  h.size = scale_terms(e.term, e.size, b, h.term);
  return h;
}

/// e * f: the sum of e scaled by each term of f.
template <int M, int N>
EXPANSE_HD inline Expansion<2 * M * N> operator*(const Expansion<M>& e, const Expansion<N>& f) {
  Expansion<2 * M * N> total;
  double scaled[2 * M];
  double merged[2 * M * N];
  for (int j = 0; j < f.size; ++j) {
    const int scaled_size = scale_terms(e.term, e.size, f.term[j], scaled);
    const int merged_size = sum_terms(total.term, total.size, scaled, scaled_size, merged);
    for (int i = 0; i < merged_size; ++i) total.term[i] = merged[i];
    total.size = merged_size;
  }
  return total;
}

/// Renormalises in place: same value, fewer terms, largest term a good approximation.
template <int M>
EXPANSE_HD inline void compress(Expansion<M>& e) {
  if (e.size <= 1) return;
  double buffer[M];
  // Sweep down: absorb each smaller term into a running sum, keeping only exact remainders.
  int bottom = e.size - 1;
  double running = e.term[e.size - 1];
  for (int i = e.size - 2; i >= 0; --i) {
    double error;
    const double sum = fast_two_sum(running, e.term[i], error);
    if (error != 0.0) {
      buffer[bottom--] = sum;
      running = error;
    } else {
      running = sum;
    }
  }
  int top = 0;
  // Sweep up: fold the high parts back in from the small end.
  for (int i = bottom + 1; i < e.size; ++i) {
    double error;
    const double sum = fast_two_sum(buffer[i], running, error);
    if (error != 0.0) buffer[top++] = error;
    running = sum;
  }
  buffer[top++] = running;
  e.size = 0;
  for (int i = 0; i < top; ++i)
    if (buffer[i] != 0.0) e.term[e.size++] = buffer[i];
}

// ---- Shared decision procedures ---------------------------------------------------------------

/// Returned by the filter and the certificate when they cannot decide the sign.
inline constexpr int uncertain = 2;

/// +1, -1, or `uncertain` when |det| <= bound (NaN included), without branches.
EXPANSE_HD inline int sign_beyond(double det, double bound) {
  const int positive = det > bound;
  const int negative = -det > bound;
  return positive - negative + uncertain * (1 - positive - negative);
}

inline constexpr double epsilon = 1.1102230246251565e-16;  // 2^-53, half an ulp of 1
/// Shewchuk's proven relative bounds (they include the rounding of the bound itself).
inline constexpr double orient2d_bound = (3.0 + 16.0 * epsilon) * epsilon;
inline constexpr double incircle_bound = (10.0 + 96.0 * epsilon) * epsilon;

// Underflow. A product that underflows loses up to 2^-1075 absolutely, which no relative bound
// covers. Adding that slack to the bound would mean computing with subnormals, which x86 does
// in microcode at ~100x the cost, so instead the filters widen the relative bound by 2^-100
// (rounding the constant up: + 2^-98) and trust themselves only where the absolute losses
// provably fit in that widening; elsewhere they answer `uncertain`.
inline constexpr double widening = 0x1p-98;
inline constexpr double orient2d_filter_bound = orient2d_bound + widening;
inline constexpr double incircle_filter_bound = incircle_bound + widening;

/// Sign of orient2d(a, b, c), or `uncertain`. No branches; no subnormal arithmetic unless the
/// input itself is that small.
EXPANSE_HD inline int orient2d_filter(double ax, double ay, double bx, double by, double cx,
                                      double cy) {
  const double left = mul(sub(ax, cx), sub(by, cy));
  const double right = mul(sub(ay, cy), sub(bx, cx));
  const double det = sub(left, right);
  const double permanent = add(magnitude(left), magnitude(right));
  // Two products lose at most 2^-1074 together: within 2^-100 * permanent once the
  // permanent is >= 2^-974 (then the bound itself is a normal number, so it is not rounded
  // more coarsely either). NaN and Inf fail every compare and end up `uncertain`.
  const bool trusted = permanent >= 0x1p-974;
  const int sign = sign_beyond(det, mul(orient2d_filter_bound, permanent));
  return trusted ? sign : uncertain;
}

/// Sign of incircle(a, b, c, d), or `uncertain`.
EXPANSE_HD inline int incircle_filter(double ax, double ay, double bx, double by, double cx,
                                      double cy, double dx, double dy) {
  const double adx = sub(ax, dx), ady = sub(ay, dy);
  const double bdx = sub(bx, dx), bdy = sub(by, dy);
  const double cdx = sub(cx, dx), cdy = sub(cy, dy);

  const double bdxcdy = mul(bdx, cdy), cdxbdy = mul(cdx, bdy);
  const double cdxady = mul(cdx, ady), adxcdy = mul(adx, cdy);
  const double adxbdy = mul(adx, bdy), bdxady = mul(bdx, ady);
  const double alift = add(mul(adx, adx), mul(ady, ady));
  const double blift = add(mul(bdx, bdx), mul(bdy, bdy));
  const double clift = add(mul(cdx, cdx), mul(cdy, cdy));

  const double det = add(add(mul(alift, sub(bdxcdy, cdxbdy)), mul(blift, sub(cdxady, adxcdy))),
                         mul(clift, sub(adxbdy, bdxady)));
  const double a_cross = add(magnitude(bdxcdy), magnitude(cdxbdy));
  const double b_cross = add(magnitude(cdxady), magnitude(adxcdy));
  const double c_cross = add(magnitude(adxbdy), magnitude(bdxady));
  const double permanent =
      add(add(mul(a_cross, alift), mul(b_cross, blift)), mul(c_cross, clift));
  // Underflow losses: an underflowed cross product's 2^-1075 is multiplied by a lift, an
  // underflowed square's by a cross term, the three final products' come unscaled; with
  // rounding, all of it is below 2^-1069 * losses_scale. Trusted when that is within
  // 2^-100 * permanent. losses_scale >= 1 keeps the scaled value normal.
  const double losses_scale =
      add(add(add(alift, blift), add(clift, a_cross)), add(add(b_cross, c_cross), 1.0));
  const bool trusted = mul(losses_scale, 0x1p-969) <= permanent;
  const int sign = sign_beyond(det, mul(incircle_filter_bound, permanent));
  return trusted ? sign : uncertain;
}

/// True when every nonzero |coordinate| lies in [2^-200, 2^200]. Then every value the exact
/// routines form (degree <= 4 in the coordinates) is a multiple of 2^-1008 and below 2^820, so
/// nothing under- or overflows and the expansions are exact. Outside this range use rationals.
EXPANSE_HD inline bool in_safe_range(double v) {
  const double m = magnitude(v);
  return v == 0.0 || (m >= 0x1p-200 && m <= 0x1p200);
}

/// Exactness certificate: evaluates the determinant in doubles and checks that every single
/// operation was exact (its error-free transformation leaves a zero remainder). If so the double
/// result is the exact value, zero included. Catches integer grids and cocircular integer
/// points. Returns the sign, or `uncertain`.
EXPANSE_HD inline int orient2d_certified(double ax, double ay, double bx, double by, double cx,
                                         double cy) {
  if (!(in_safe_range(ax) && in_safe_range(ay) && in_safe_range(bx) && in_safe_range(by) &&
        in_safe_range(cx) && in_safe_range(cy)))
    return uncertain;
  double e0, e1, e2, e3, e4, e5, e6;
  const double acx = two_diff(ax, cx, e0), bcy = two_diff(by, cy, e1);
  const double acy = two_diff(ay, cy, e2), bcx = two_diff(bx, cx, e3);
  const double left = two_product(acx, bcy, e4);
  const double right = two_product(acy, bcx, e5);
  const double det = two_diff(left, right, e6);
  // Bitwise-or of "nonzero" without branches: any nonzero remainder spoils the certificate.
  const bool exact = (e0 == 0.0) & (e1 == 0.0) & (e2 == 0.0) & (e3 == 0.0) & (e4 == 0.0) &
                     (e5 == 0.0) & (e6 == 0.0);
  if (!exact) return uncertain;
  return (det > 0.0) - (det < 0.0);
}

EXPANSE_HD inline int incircle_certified(double ax, double ay, double bx, double by, double cx,
                                         double cy, double dx, double dy) {
  if (!(in_safe_range(ax) && in_safe_range(ay) && in_safe_range(bx) && in_safe_range(by) &&
        in_safe_range(cx) && in_safe_range(cy) && in_safe_range(dx) && in_safe_range(dy)))
    return uncertain;
  bool exact = true;
  auto diff = [&](double p, double q) {
    double error;
    const double r = two_diff(p, q, error);
    exact = exact & (error == 0.0);
    return r;
  };
  auto sum = [&](double p, double q) {
    double error;
    const double r = two_sum(p, q, error);
    exact = exact & (error == 0.0);
    return r;
  };
  auto product = [&](double p, double q) {
    double error;
    const double r = two_product(p, q, error);
    exact = exact & (error == 0.0);
    return r;
  };
  const double adx = diff(ax, dx), ady = diff(ay, dy);
  const double bdx = diff(bx, dx), bdy = diff(by, dy);
  const double cdx = diff(cx, dx), cdy = diff(cy, dy);
  const double alift = sum(product(adx, adx), product(ady, ady));
  const double blift = sum(product(bdx, bdx), product(bdy, bdy));
  const double clift = sum(product(cdx, cdx), product(cdy, cdy));
  const double a_term = product(alift, diff(product(bdx, cdy), product(cdx, bdy)));
  const double b_term = product(blift, diff(product(cdx, ady), product(adx, cdy)));
  const double c_term = product(clift, diff(product(adx, bdy), product(bdx, ady)));
  const double det = sum(sum(a_term, b_term), c_term);
  if (!exact) return uncertain;
  return (det > 0.0) - (det < 0.0);
}

// ---- Exact evaluation in expansions (valid when all coordinates are in_safe_range) -----------

EXPANSE_HD inline int orient2d_expansion(double ax, double ay, double bx, double by, double cx,
                                         double cy) {
  const Expansion<2> acx = exact_difference(ax, cx), bcy = exact_difference(by, cy);
  const Expansion<2> acy = exact_difference(ay, cy), bcx = exact_difference(bx, cx);
  return (acx * bcy - acy * bcx).sign();
}

/// Adds x to the expansion h[0 .. *size) in place (Shewchuk's GROW-EXPANSION-ZEROELIM: h stays
/// in increasing magnitude, non-overlapping, without zeros). False when it would not fit in
/// `capacity` terms.
EXPANSE_HD inline bool grow_terms(double* h, int* size, int capacity, double x) {
  double q = x;
  int out = 0;
  for (int i = 0; i < *size; ++i) {
    double error;
    q = two_sum(q, h[i], error);
    if (error != 0.0) h[out++] = error;
  }
  if (q != 0.0 || out == 0) {
    if (out == capacity) return false;
    h[out++] = q;
  }
  *size = out;
  return true;
}

/// a - d, b - d, c - d into diff[0 .. 6) (x, y each), when the coordinates are in the safe range
/// and every difference is exact (its two_diff remainder zero).
EXPANSE_HD inline bool exact_differences_against(double ax, double ay, double bx, double by, double cx, double cy,
                                                 double dx, double dy, double* diff) {
  if (!(in_safe_range(ax) && in_safe_range(ay) && in_safe_range(bx) && in_safe_range(by) &&
        in_safe_range(cx) && in_safe_range(cy) && in_safe_range(dx) && in_safe_range(dy)))
    return false;
  double e0, e1, e2, e3, e4, e5;
  diff[0] = two_diff(ax, dx, e0);
  diff[1] = two_diff(ay, dy, e1);
  diff[2] = two_diff(bx, dx, e2);
  diff[3] = two_diff(by, dy, e3);
  diff[4] = two_diff(cx, dx, e4);
  diff[5] = two_diff(cy, dy, e5);
  return (e0 == 0.0) & (e1 == 0.0) & (e2 == 0.0) & (e3 == 0.0) & (e4 == 0.0) & (e5 == 0.0);
}

/// incircle's exact sign where the six coordinate differences against d are exact (their
/// error-free remainders zero), or `uncertain` where one is not (or a coordinate is outside the
/// safe range). Each difference is then one double, so the determinant's expansions stay small
/// (at most 4 terms per 2 x 2 minor and per lift, 32 per product, 96 in all: about 2 KB, where
/// incircle_expansion needs ~40 KB; devices use the 320-byte form below). Nearby sites
/// of one magnitude always qualify (Sterbenz: y / 2 <= x <= 2 y makes x - y exact), so decimal
/// grids and other nearly cocircular float inputs are decided here; only differences across a
/// coordinate's sign change or binade boundary near zero may not be.
EXPANSE_HD inline int incircle_exact_differences(double ax, double ay, double bx, double by, double cx,
                                                 double cy, double dx, double dy) {
  double diff[6];
  if (!exact_differences_against(ax, ay, bx, by, cx, cy, dx, dy, diff)) return uncertain;
  const double adx = diff[0], ady = diff[1], bdx = diff[2], bdy = diff[3], cdx = diff[4], cdy = diff[5];
  const Expansion<4> bc = exact_product(bdx, cdy) - exact_product(cdx, bdy);
  const Expansion<4> ca = exact_product(cdx, ady) - exact_product(adx, cdy);
  const Expansion<4> ab = exact_product(adx, bdy) - exact_product(bdx, ady);
  const Expansion<4> alift = exact_product(adx, adx) + exact_product(ady, ady);
  const Expansion<4> blift = exact_product(bdx, bdx) + exact_product(bdy, bdy);
  const Expansion<4> clift = exact_product(cdx, cdx) + exact_product(cdy, cdy);
  return (alift * bc + blift * ca + clift * ab).sign();
}

/// incircle_exact_differences's sign for device threads: the determinant as the exact sum of its
/// 96 exact products (each lift and each 2 x 2 minor a sum of four doubles from two_product),
/// grown term by term into one expansion of at most 40 doubles (320 bytes of stack, against the
/// 2 KB of arrays that multiplying out takes). On the H100 the CUDA star kernels took 451 ms
/// for a 4096^2 decimal grid against 1,049 multiplied out; on the host's cores it is the slower
/// (the CPU backend on a 250k decimal grid: 390 against 245 ms), so the host multiplies out.
/// shaders/include/predicates.glsl evaluates it the same way. `uncertain` also where the
/// expansion would not fit (it always fits within the safe range).
EXPANSE_HD inline int incircle_exact_differences_grown(double ax, double ay, double bx, double by, double cx,
                                                       double cy, double dx, double dy) {
  double diff[6];
  if (!exact_differences_against(ax, ay, bx, by, cx, cy, dx, dy, diff)) return uncertain;
  const double adx = diff[0], ady = diff[1], bdx = diff[2], bdy = diff[3], cdx = diff[4], cdy = diff[5];
  constexpr int capacity = 40;  // a non-overlapping expansion within the safe range needs fewer
  double h[capacity];
  int size = 0;
  // lift(u) (v.x w.y - w.x v.y) for (u, v, w) = (a, b, c), (b, c, a), (c, a, b).
  const double ux[3] = {adx, bdx, cdx}, uy[3] = {ady, bdy, cdy};
  for (int t = 0; t < 3; ++t) {
    const int v = (t + 1) % 3, w = (t + 2) % 3;
    double lift[4], minor[4];
    lift[0] = two_product(ux[t], ux[t], lift[1]);
    lift[2] = two_product(uy[t], uy[t], lift[3]);
    minor[0] = two_product(ux[v], uy[w], minor[1]);
    double m_low;
    const double m_high = two_product(ux[w], uy[v], m_low);
    minor[2] = -m_high;
    minor[3] = -m_low;
    for (int k = 0; k < 16; ++k) {
      double error;
      const double product = two_product(lift[k >> 2], minor[k & 3], error);
      if (!grow_terms(h, &size, capacity, error) || !grow_terms(h, &size, capacity, product)) return uncertain;
    }
  }
  const double top = size == 0 ? 0.0 : h[size - 1];  // a zero sum leaves one zero term
  return (top > 0.0) - (top < 0.0);
}

/// Needs ~40 KB of stack: fine on the host, a last resort on devices.
EXPANSE_HD inline int incircle_expansion(double ax, double ay, double bx, double by, double cx,
                                         double cy, double dx, double dy) {
  const Expansion<2> adx = exact_difference(ax, dx), ady = exact_difference(ay, dy);
  const Expansion<2> bdx = exact_difference(bx, dx), bdy = exact_difference(by, dy);
  const Expansion<2> cdx = exact_difference(cx, dx), cdy = exact_difference(cy, dy);
  // Not compressed between steps: sum_terms needs strongly non-overlapping inputs, which the
  // zero-eliminating sum and scale preserve; zero elimination already keeps sizes small.
  const Expansion<16> bc = bdx * cdy - cdx * bdy;
  const Expansion<16> ca = cdx * ady - adx * cdy;
  const Expansion<16> ab = adx * bdy - bdx * ady;
  const Expansion<16> alift = adx * adx + ady * ady;
  const Expansion<16> blift = bdx * bdx + bdy * bdy;
  const Expansion<16> clift = cdx * cdx + cdy * cdy;
  return (alift * bc + blift * ca + clift * ab).sign();
}

}  // namespace expanse::detail::exact
