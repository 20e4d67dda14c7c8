// Star bookkeeping shared by star.comp (which writes the stars) and star_links.comp (which
// derives adjacency from them); the info word and the row length are host_device.h's (the host
// reads the stars too); the CUDA backend keeps its own (cuda_backend/star_common.cuh).
//
// The star of s is row s of `star4[]`: 16 ints as four ivec4, read and written whole (on
// lavapipe every buffer access costs a loop over the lanes, whatever its width, so one ivec4
// costs what one int does). The t-th neighbour counter-clockwise is at row index
// (start + t) & 15. No integer division
// anywhere: lavapipe has no vector integer divide and runs `%` lane by lane.
#ifndef EXPANSE_STAR_COMMON_GLSL
#define EXPANSE_STAR_COMMON_GLSL

#include "host_device.h"

// Output index of the t-th triangle of an owner whose first triangle is `base`.
int star_output(int base, uint info, int t) {
  return base + bitCount(star_owned(info) & ((1u << uint(t)) - 1u));
}

struct StarRow {
  ivec4 q0, q1, q2, q3;
};

// Row index j in [0, 16), with selects only (no indexing a vector by a variable).
int row_pick(StarRow r, int j) {
  ivec4 q = j < 8 ? (j < 4 ? r.q0 : r.q1) : (j < 12 ? r.q2 : r.q3);
  int k = j & 3;
  return k < 2 ? (k == 0 ? q.x : q.y) : (k == 2 ? q.z : q.w);
}

void row_put(inout StarRow r, int j, int value) {
  ivec4 v = ivec4(value);
  r.q0 = mix(r.q0, v, equal(ivec4(j), ivec4(0, 1, 2, 3)));
  r.q1 = mix(r.q1, v, equal(ivec4(j), ivec4(4, 5, 6, 7)));
  r.q2 = mix(r.q2, v, equal(ivec4(j), ivec4(8, 9, 10, 11)));
  r.q3 = mix(r.q3, v, equal(ivec4(j), ivec4(12, 13, 14, 15)));
}

// Row index of the t-th neighbour counter-clockwise; t in [-deg, 2 deg) wraps (meaningful for
// closed stars).
int star_slot(uint info, int t) {
  int deg = star_degree(info);
  if (t < 0) t += deg;
  if (t >= deg) t -= deg;
  return (star_start(info) + t) & 15;
}

int star_at(StarRow r, uint info, int t) { return row_pick(r, star_slot(info, t)); }

// Position t of u in the star, or -1. Row entries outside the star are ignored (never written).
int star_find(StarRow r, uint info, int u) {
  const uvec4 w = uvec4(1u, 2u, 4u, 8u);
  uvec4 m = uvec4(equal(r.q0, ivec4(u))) * w + (uvec4(equal(r.q1, ivec4(u))) * w << 4) +
            (uvec4(equal(r.q2, ivec4(u))) * w << 8) + (uvec4(equal(r.q3, ivec4(u))) * w << 12);
  uint hits = m.x | m.y | m.z | m.w;
  uint start = uint(star_start(info));
  uint span = (1u << uint(star_degree(info))) - 1u;
  uint valid = ((span << start) | (span >> (16u - start))) & 0xffffu;
  hits &= valid;
  return hits == 0u ? -1 : ((findLSB(hits) - int(start)) & 15);
}

#endif
