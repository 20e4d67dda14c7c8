#version 450
// Test kernel: evaluates the device predicates and error-free transformations on a batch of
// inputs so the host can compare them with its own (tests/vulkan, and the start-up self-test).
#extension GL_ARB_gpu_shader_fp64 : enable
#extension GL_GOOGLE_include_directive : require

#include "host_device.h"

layout(local_size_x_id = 0) in;

// Per case: 4 points (8 doubles).
layout(std430, set = 0, binding = 0) readonly buffer Cases { double cases[]; };
// Per case: 12 ints: orient filter, orient certified, orient device, incircle filter,
// incircle certified, incircle device, incircle perturbed, the apex filters in the frame of
// a->b: orient2d(a, b, c), orient2d(a, b, d), incircle(a, b, c, d); incircle from exact
// differences, orient2d(a, b, c) from exact differences.
layout(std430, set = 0, binding = 1) writeonly buffer Signs { int signs[]; };
// Per case: 4 doubles: two_sum(x0, y0) error, two_product(x0, y0) result and error,
// and x0 * y0 + x1 evaluated under `precise` (must not be an fma).
layout(std430, set = 0, binding = 2) writeonly buffer Eft { double eft[]; };

layout(push_constant) uniform Push { PredicateTestParams params; };

#include "predicates.glsl"

void main() {
  int i = int(gl_GlobalInvocationID.x);
  if (i >= params.count) return;
  dvec2 a = dvec2(cases[8 * i + 0], cases[8 * i + 1]);
  dvec2 b = dvec2(cases[8 * i + 2], cases[8 * i + 3]);
  dvec2 c = dvec2(cases[8 * i + 4], cases[8 * i + 5]);
  dvec2 d = dvec2(cases[8 * i + 6], cases[8 * i + 7]);
  signs[PREDICATE_TEST_SIGNS * i + 0] = orient2d_filter(a, b, c);
  signs[PREDICATE_TEST_SIGNS * i + 1] = orient2d_certified(a, b, c);
  signs[PREDICATE_TEST_SIGNS * i + 2] = orient2d_device(a, b, c);
  signs[PREDICATE_TEST_SIGNS * i + 3] = incircle_filter(a, b, c, d);
  signs[PREDICATE_TEST_SIGNS * i + 4] = incircle_certified(a, b, c, d);
  signs[PREDICATE_TEST_SIGNS * i + 5] = incircle_device(a, b, c, d);
  int o = orient2d_device(a, b, c);
  signs[PREDICATE_TEST_SIGNS * i + 6] = o == 1 ? incircle_perturbed_device(a, b, c, d) : 0;
  precise dvec2 edge = b - a;
  precise double b2 = edge.x * edge.x + edge.y * edge.y;
  ApexLift c_lift = apex_lift(edge, b2, apex_point(a, c));
  dvec3 d_point = apex_point(a, d);
  signs[PREDICATE_TEST_SIGNS * i + 7] = apex_orient_filter(c_lift);
  signs[PREDICATE_TEST_SIGNS * i + 8] = apex_orient_filter(apex_lift(edge, b2, d_point));
  signs[PREDICATE_TEST_SIGNS * i + 9] = apex_incircle_filter(c_lift, d_point);
  signs[PREDICATE_TEST_SIGNS * i + 10] = incircle_exact_differences(a, b, c, d);
  signs[PREDICATE_TEST_SIGNS * i + 11] = orient2d_exact_differences(a, b, c);
  double e;
  two_sum(a.x, a.y, e);
  eft[PREDICATE_TEST_EFT * i + 0] = e;
  double pe;
  eft[PREDICATE_TEST_EFT * i + 1] = two_product(a.x, a.y, pe);
  eft[PREDICATE_TEST_EFT * i + 2] = pe;
  precise double r = a.x * a.y + b.x;
  eft[PREDICATE_TEST_EFT * i + 3] = r;
}
