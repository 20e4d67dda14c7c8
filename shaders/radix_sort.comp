#version 450
// One pass of a stable least-significant-digit radix sort of (64-bit key, 32-bit value) pairs,
// four bits a pass, for the site preparation on the device (device_preparation.cpp records the
// passes). Keys are uvec2 (low word, high word): no 64-bit integer types are needed.
//
//   RADIX_PASS_COUNT    each workgroup counts its tile's digits; counts[d * tiles + tile]
//   (scan.comp)   inclusive scan of counts: digit-major, so it orders (digit, tile)
//   RADIX_PASS_SCATTER  each workgroup ranks its tile's elements stably and moves them to their place
//
// The pairs live on two sides (buffers 0/2 and 1/3); params.side says which one this pass
// reads, and it writes the other (one descriptor set for every pass of a recording).
//
// Stable ranking without subgroup operations (lavapipe's subgroups are 8 wide, NVIDIA's 32):
// invocation t owns ITEMS consecutive elements of the tile. The shared table rank[d][t] holds
// how many of its elements have digit d; an exclusive scan of the table in digit-major order
// gives each (digit, invocation) the number of the tile's elements before it in sorted order.
#extension GL_GOOGLE_include_directive : require

#include "host_device.h"

layout(local_size_x_id = 0) in;
const int ITEMS = RADIX_ITEMS;
const int RADIX = RADIX_DIGITS;
const int WORKGROUP = int(gl_WorkGroupSize.x);
const int TILE = WORKGROUP * ITEMS;


layout(std430, set = 0, binding = 0) buffer Keys0 { uvec2 keys0[]; };
layout(std430, set = 0, binding = 1) buffer Keys1 { uvec2 keys1[]; };
layout(std430, set = 0, binding = 2) buffer Values0 { uint values0[]; };
layout(std430, set = 0, binding = 3) buffer Values1 { uint values1[]; };
layout(std430, set = 0, binding = 4) buffer Counts { int counts[]; };

layout(push_constant) uniform Push { RadixParams params; };

shared int table[RADIX * WORKGROUP];
shared int totals[WORKGROUP];
shared int digit_base[RADIX];

uvec2 key_at(int i) { return params.side == 0 ? keys0[i] : keys1[i]; }
uint value_at(int i) { return params.side == 0 ? values0[i] : values1[i]; }
void put(int i, uvec2 key, uint value) {
  if (params.side == 0) {
    keys1[i] = key;
    values1[i] = value;
  } else {
    keys0[i] = key;
    values0[i] = value;
  }
}

int digit_of(uvec2 key) {
  const int s = params.shift;
  return int(s < 32 ? (key.x >> s) & 15u : (key.y >> (s - 32)) & 15u);
}

void main() {
  const int tile = params.first_tile + int(gl_WorkGroupID.x);
  const int local = int(gl_LocalInvocationID.x);
  const int tile_begin = tile * TILE;

  if (params.pass == RADIX_PASS_COUNT) {
    if (local < RADIX) table[local] = 0;
    barrier();
    for (int k = 0; k < ITEMS; ++k) {  // coalesced: invocations read neighbouring elements
      const int i = tile_begin + k * WORKGROUP + local;
      if (i < params.count) atomicAdd(table[digit_of(key_at(i))], 1);
    }
    barrier();
    if (local < RADIX) counts[local * params.tiles + tile] = table[local];
    return;
  }

  // RADIX_PASS_SCATTER: this invocation's elements, their digits counted in its column of the table.
  for (int d = 0; d < RADIX; ++d) table[d * WORKGROUP + local] = 0;
  uvec2 keys[ITEMS];
  uint values[ITEMS];
  int digits[ITEMS];
  const int mine = tile_begin + local * ITEMS;
  for (int k = 0; k < ITEMS; ++k) {
    digits[k] = -1;
    if (mine + k < params.count) {
      keys[k] = key_at(mine + k);
      values[k] = value_at(mine + k);
      digits[k] = digit_of(keys[k]);
      table[digits[k] * WORKGROUP + local] += 1;
    }
  }
  barrier();
  // Exclusive scan of the table, flat and digit-major: each invocation sums RADIX neighbouring
  // entries (a stretch of the flat table, not its own column), Hillis-Steele over the sums,
  // then each writes its stretch's exclusive prefixes back.
  int running = 0;
  for (int j = 0; j < RADIX; ++j) running += table[local * RADIX + j];
  totals[local] = running;
  barrier();
  for (int step = 1; step < WORKGROUP; step <<= 1) {
    const int add = local >= step ? totals[local - step] : 0;
    barrier();
    totals[local] += add;
    barrier();
  }
  running = local > 0 ? totals[local - 1] : 0;
  for (int j = 0; j < RADIX; ++j) {
    const int here = table[local * RADIX + j];
    table[local * RADIX + j] = running;
    running += here;
  }
  barrier();
  // Digit d's elements of this tile go to [counts'[d][tile] - their number, counts'[d][tile])
  // (counts' scanned, inclusive); their number is table[d + 1][0] - table[d][0], the tile's
  // element count for the last digit.
  if (local < RADIX) {
    const int next = local + 1 < RADIX ? table[(local + 1) * WORKGROUP] : totals[WORKGROUP - 1];
    digit_base[local] = counts[local * params.tiles + tile] - next;
  }
  barrier();
  // Element (local, k) of digit d goes after the tile's elements of digit d before it: those of
  // lower invocations (the table's entry) and this invocation's earlier ones (counted on).
  for (int k = 0; k < ITEMS; ++k) {
    const int d = digits[k];
    if (d < 0) continue;
    const int slot = d * WORKGROUP + local;
    put(digit_base[d] + table[slot], keys[k], values[k]);
    table[slot] += 1;
  }
}
