// Error-free transformations in GLSL, mirroring engine/src/predicates/exact_arith.hpp operation
// for operation, so that a sign decided here is the sign the host decides.
//
// Every temporary is `precise`: without it a driver may contract a*b+c into one fma, which
// silently zeroes the remainders below (glslang emits NoContraction for precise values). fma()
// itself is never used: lavapipe lowers a 64-bit fma to a separate multiply and add anyway.
#ifndef EXPANSE_EFT_GLSL
#define EXPANSE_EFT_GLSL

#extension GL_ARB_gpu_shader_fp64 : enable

double mag(double a) { return a < 0.0lf ? -a : a; }

double two_sum(double a, double b, out double error) {
  precise double s = a + b;
  precise double b_part = s - a;
  precise double a_part = s - b_part;
  precise double e = (a - a_part) + (b - b_part);
  error = e;
  return s;
}

double two_diff(double a, double b, out double error) {
  precise double d = a - b;
  precise double b_part = a - d;
  precise double a_part = d + b_part;
  precise double e = (a - a_part) + (b_part - b);
  error = e;
  return d;
}

void split(double a, out double high, out double low) {
  precise double scaled = 134217729.0lf * a;  // 2^27 + 1
  precise double big = scaled - a;
  precise double h = scaled - big;
  precise double l = a - h;
  high = h;
  low = l;
}

double two_product(double a, double b, out double error) {
  precise double p = a * b;
  double ah, al, bh, bl;
  split(a, ah, al);
  split(b, bh, bl);
  precise double r1 = p - ah * bh;
  precise double r2 = r1 - al * bh;
  precise double r3 = r2 - ah * bl;
  precise double e = al * bl - r3;
  error = e;
  return p;
}

#endif
