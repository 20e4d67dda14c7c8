// Star bookkeeping shared by star.comp (which writes the stars) and star_links.comp (which
// derives adjacency from them); mirrors cuda_backend/star_common.cuh.
//
// The including kernel declares STAR_CAPACITY (row length) and a readable buffer `star[]`
// holding row s = the star of site s, and packs per-site info as
//   bits 0-7 degree, bits 8-15 start index in the row, STAR_CLOSED, STAR_DEFERRED.
#ifndef EXPANSE_STAR_COMMON_GLSL
#define EXPANSE_STAR_COMMON_GLSL

const uint STAR_CLOSED = 1u << 16;
const uint STAR_DEFERRED = 1u << 17;

int star_degree(uint info) { return int(info & 255u); }
int star_start(uint info) { return int((info >> 8) & 255u); }
bool star_closed(uint info) { return (info & STAR_CLOSED) != 0u; }
bool star_deferred(uint info) { return (info & STAR_DEFERRED) != 0u; }

// The t-th neighbour counter-clockwise of the site whose row starts at `row`; t in [-deg, 2 deg)
// wraps (meaningful for closed stars). Operands of % are kept non-negative.
int star_at_row(int row, uint info, int t) {
  int deg = star_degree(info);
  t = (t + deg) % deg;
  return star[row + (star_start(info) + t) % STAR_CAPACITY];
}

#endif
