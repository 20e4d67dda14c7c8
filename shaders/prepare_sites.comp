#version 450
// The raw input prepared on the device, as prepare_sites does it on the host (and the CUDA
// backend on its device): scaled by the host's power of two, sorted in Morton order
// (radix_sort.comp, stable: input order within a code), duplicates merged (the smallest input
// index represents each group), the groups' first points compacted into the sites. The passes,
// selected by params.pass and recorded by device_preparation.cpp:
//
//   PREPARE_PASS_CODES          scale each point in place; its Morton code and input index (side 0)
//   (radix_sort.comp)   by the 60-bit codes
//   PREPARE_PASS_GATHER         the points in sorted order
//   PREPARE_PASS_FIRST_EQUAL    the first position of a run of equal codes holding a point equal to
//                       p's (p itself if none); heads[p] = 1 where that is p. A run longer than
//                       RUN_LIMIT sets counters[PREPARE_COUNTER_LONG_RUN] instead, and the host sorts again:
//   PREPARE_PASS_KEYS           (then) the key of sort number params.mode for the points in the current
//                       order: 0 y, 1 x (their bits in an order that follows the value, -0 as
//                       +0), 2 the code; three stable sorts order by (code, x, y)
//   PREPARE_PASS_GROUP_START    (then) heads[p] = 1 where p differs from the point before it
//   (scan.comp)         inclusive scan of the heads: position p's group is heads'[p] - 1
//   PREPARE_PASS_HEAD_POSITION  (then) where each group starts, into rank[]
//   PREPARE_PASS_FIRST_OF_GROUP (then) first[p] from it
//   PREPARE_PASS_COMPACT        the heads become the sites (in Morton order); each input index gets
//                       its group's site (rank) and first input index (representative);
//                       counters[PREPARE_COUNTER_SITES] = the number of sites
//   PREPARE_PASS_HULL           the hull's input indices -> site ids
//   PREPARE_PASS_PREDECESSOR    the hull predecessors, in site ids (the rest filled with -1 before)
//   PREPARE_PASS_SAMPLE         every params.mode-th site into sorted[] (the grid's sample, star_cells.hpp)
#extension GL_ARB_gpu_shader_fp64 : enable
#extension GL_GOOGLE_include_directive : require

#include "host_device.h"

layout(local_size_x_id = 0) in;
const int RUN_LIMIT = 64;  // as the CUDA backend's kMergeRunLimit


layout(std430, set = 0, binding = 0) buffer Raw { dvec2 raw[]; };  // input order, scaled in place
layout(std430, set = 0, binding = 1) buffer Keys0 { uvec2 keys0[]; };
layout(std430, set = 0, binding = 2) buffer Keys1 { uvec2 keys1[]; };
layout(std430, set = 0, binding = 3) buffer Values0 { int values0[]; };
layout(std430, set = 0, binding = 4) buffer Values1 { int values1[]; };
layout(std430, set = 0, binding = 5) buffer Sorted { dvec2 sorted[]; };  // the points in sorted order
layout(std430, set = 0, binding = 6) buffer First { int first[]; };
layout(std430, set = 0, binding = 7) buffer Heads { int heads[]; };     // scanned in place
layout(std430, set = 0, binding = 8) buffer SitePoints { dvec2 site_points[]; };
layout(std430, set = 0, binding = 9) writeonly buffer SiteInput { int site_input[]; };
layout(std430, set = 0, binding = 10) buffer Rank { int rank[]; };      // input index -> site
layout(std430, set = 0, binding = 11) writeonly buffer Representative { int representative[]; };
layout(std430, set = 0, binding = 12) readonly buffer HullInput { int hull_input[]; };
layout(std430, set = 0, binding = 13) buffer HullSites { int hull_sites[]; };
layout(std430, set = 0, binding = 14) writeonly buffer Predecessor { int predecessor[]; };
layout(std430, set = 0, binding = 15) buffer Counters { uint counters[]; };

layout(push_constant) uniform Push { PrepareParams params; };

// Quantiser::x / y (input/morton.hpp), the same correctly rounded operations.
uint quantise(double v, double origin) {
  precise double q = (v - origin) * params.scale;
  const double most = double((1u << 30) - 1u);
  if (!(q > 0.0lf)) return 0u;
  if (q >= most) return (1u << 30) - 1u;
  return uint(q);
}

// Bits 0..15 of v to the even bits.
uint spread16(uint v) {
  v = (v | (v << 8)) & 0x00FF00FFu;
  v = (v | (v << 4)) & 0x0F0F0F0Fu;
  v = (v | (v << 2)) & 0x33333333u;
  v = (v | (v << 1)) & 0x55555555u;
  return v;
}

// morton_code(qx, qy) as (low word, high word): x on the even bits, y on the odd ones.
uvec2 morton(dvec2 p) {
  const uint qx = quantise(p.x, params.origin.x), qy = quantise(p.y, params.origin.y);
  return uvec2(spread16(qx & 0xFFFFu) | (spread16(qy & 0xFFFFu) << 1),
               spread16(qx >> 16) | (spread16(qy >> 16) << 1));
}

// v's bits as an unsigned number in the order of v, -0 as +0 (the two are equal points).
uvec2 ordered_bits(double v) {
  const uvec2 bits = unpackDouble2x32(v == 0.0lf ? 0.0lf : v);
  return (bits.y >> 31) != 0u ? ~bits : uvec2(bits.x, bits.y | 0x80000000u);
}

int id_at(int k) { return params.side == 0 ? values0[k] : values1[k]; }
uvec2 key_at(int k) { return params.side == 0 ? keys0[k] : keys1[k]; }

bool same_point(dvec2 a, dvec2 b) { return a.x == b.x && a.y == b.y; }

void main() {
  const int i = params.first + int(gl_GlobalInvocationID.x);
  if (i >= params.count) return;
  if (params.pass == PREPARE_PASS_CODES) {
    precise dvec2 p = raw[i] * params.factor;
    if (params.second_factor != 1.0lf) p = p * params.second_factor;
    raw[i] = p;
    keys0[i] = morton(p);
    values0[i] = i;
  } else if (params.pass == PREPARE_PASS_KEYS) {
    const dvec2 p = raw[id_at(i)];
    const uvec2 key = params.mode == 0 ? ordered_bits(p.y) : params.mode == 1 ? ordered_bits(p.x) : morton(p);
    if (params.side == 0)
      keys0[i] = key;
    else
      keys1[i] = key;
  } else if (params.pass == PREPARE_PASS_GATHER) {
    sorted[i] = raw[id_at(i)];
  } else if (params.pass == PREPARE_PASS_FIRST_EQUAL) {
    const uvec2 code = key_at(i);
    int begin = i;
    while (begin > 0 && key_at(begin - 1) == code && i - begin < RUN_LIMIT) --begin;
    int q = i;
    if (begin > 0 && key_at(begin - 1) == code) {
      atomicAdd(counters[PREPARE_COUNTER_LONG_RUN], 1u);
    } else {
      const dvec2 v = sorted[i];
      for (int j = begin; j < i; ++j) {
        if (same_point(sorted[j], v)) {
          q = j;
          break;
        }
      }
    }
    first[i] = q;
    heads[i] = q == i ? 1 : 0;
  } else if (params.pass == PREPARE_PASS_GROUP_START) {
    heads[i] = i == 0 || !same_point(sorted[i - 1], sorted[i]) ? 1 : 0;
  } else if (params.pass == PREPARE_PASS_HEAD_POSITION) {
    if (i == 0 || heads[i] != heads[i - 1]) rank[heads[i] - 1] = i;
  } else if (params.pass == PREPARE_PASS_FIRST_OF_GROUP) {
    first[i] = rank[heads[i] - 1];
  } else if (params.pass == PREPARE_PASS_COMPACT) {
    const int group = heads[i];
    const int input_index = id_at(i), f = first[i];
    if (i == 0 || group != heads[i - 1]) {
      site_points[group - 1] = sorted[i];
      site_input[group - 1] = input_index;
    }
    rank[input_index] = heads[f] - 1;
    representative[input_index] = id_at(f);
    if (i == params.count - 1) counters[PREPARE_COUNTER_SITES] = uint(group);
  } else if (params.pass == PREPARE_PASS_HULL) {
    hull_sites[i] = rank[hull_input[i]];
  } else if (params.pass == PREPARE_PASS_PREDECESSOR) {
    predecessor[hull_sites[i]] = hull_sites[(i + params.count - 1) % params.count];
  } else if (params.pass == PREPARE_PASS_SAMPLE) {
    sorted[i] = site_points[i * params.mode];
  }
}
