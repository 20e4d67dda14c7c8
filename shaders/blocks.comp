#version 450
// The paper's layout (docs/algorithm.md, "GPU, the paper's layout"): one workgroup per block
// grows the block's triangulation from its seed, iteration by iteration, its invocations
// striding over the block's active edges. A block sees its own sites plus a halo copied from its
// neighbours; an expansion is accepted only when its empty-circle region lies inside that copy.
#extension GL_ARB_gpu_shader_fp64 : enable
#extension GL_GOOGLE_include_directive : require

#include "host_device.h"

layout(local_size_x_id = 0) in;
// Loop iterations one invocation may spend on searches before it leaves its edges open for the
// seam stage (lavapipe's loop cap, see grid.glsl).
layout(constant_id = 1) const int LOOP_BUDGET = 1000000000;

layout(std430, set = 0, binding = 0) readonly buffer Sites { dvec2 sites[]; };
layout(std430, set = 0, binding = 1) readonly buffer LocalIds { int local_ids[]; };
layout(std430, set = 0, binding = 2) readonly buffer CellStart { int cell_start[]; };
layout(std430, set = 0, binding = 3) readonly buffer Predecessor { int predecessor[]; };
layout(std430, set = 0, binding = 4) readonly buffer Owner { int owner[]; };
// Per block, 12 ints: ext cell range lo.x lo.y hi.x hi.y, cell_base, slot_base, local count,
// seed slot (-1: none), hash_base, hash_capacity, active_base, active_capacity.
layout(std430, set = 0, binding = 5) readonly buffer Blocks { int blocks[]; };
// Directed edges (la << 16 | lb, block-local slots) that have their left triangle; ~0u empty.
layout(std430, set = 0, binding = 6) coherent buffer EdgeSet { uint edge_set[]; };
// Two active lists per block (this iteration's and the next's).
layout(std430, set = 0, binding = 7) coherent buffer Active { uint active_edges[]; };
layout(std430, set = 0, binding = 8) writeonly buffer Triangles { int triangles[]; };
// [0] triangles written, [1] deferred expansions, [2] output overflow, [3] most iterations,
// [4] edges left open (region outside the block), [5] active/edge-set overflow
layout(std430, set = 0, binding = 9) buffer Counters { uint counters[]; };

layout(push_constant) uniform Push { BlockParams params; };

dvec2 site_at(int id) { return sites[id]; }
int cell_begin(int cell) { return cell_start[cell]; }
int slot_site(int slot) { return local_ids[slot]; }

#include "grid.glsl"

const uint EMPTY = 0xffffffffu;

shared uint s_count;
shared uint s_next;
shared uint s_iterations;

int slot_base;
int hash_base;
int hash_capacity;
int active_base;
int active_capacity;

uint edge_key(int la, int lb) { return (uint(la) << 16) | uint(lb); }

uint hash_start(uint key) { return (key * 2654435761u) % uint(hash_capacity); }

// 1: inserted, 0: already there, -1: table full (treated as "not mine": never emit twice).
int edge_insert(int la, int lb) {
  uint key = edge_key(la, lb);
  uint h = hash_start(key);
  for (int probe = 0; probe < hash_capacity; ++probe) {
    uint seen = atomicCompSwap(edge_set[hash_base + int(h)], EMPTY, key);
    if (seen == EMPTY) return 1;
    if (seen == key) return 0;
    h = h + 1u == uint(hash_capacity) ? 0u : h + 1u;
  }
  atomicAdd(counters[COUNTER_BLOCK_ACTIVE_OVERFLOW], 1u);
  return -1;
}

bool edge_known(int la, int lb) {
  uint key = edge_key(la, lb);
  uint h = hash_start(key);
  for (int probe = 0; probe < hash_capacity; ++probe) {
    uint seen = edge_set[hash_base + int(h)];
    if (seen == key) return true;
    if (seen == EMPTY) return false;
    h = h + 1u == uint(hash_capacity) ? 0u : h + 1u;
  }
  return false;
}

void push_edge(int parity, int la, int lb) {
  uint at = atomicAdd(s_next, 1u);
  if (int(at) >= active_capacity) return;  // counted as overflow after the barrier
  active_edges[active_base + parity * active_capacity + int(at)] = edge_key(la, lb);
}

void expand(Grid g, int block, int next_parity, uint edge) {
  if (loop_budget < 0) {
    atomicAdd(counters[COUNTER_DEFERRED], 1u);
    return;
  }
  int la = int(edge >> 16), lb = int(edge & 0xffffu);
  if (edge_known(la, lb)) return;  // another expansion already made its triangle
  int a = local_ids[slot_base + la], b = local_ids[slot_base + lb];
  if (predecessor[a] == b) return;  // outer hull edge: no apex
  int c, c_slot;
  int status = apex_search(g, a, b, sites[a], sites[b], c, c_slot);
  if (status == SEARCH_DEFER) {
    atomicAdd(counters[COUNTER_DEFERRED], 1u);
    return;
  }
  if (status != SEARCH_FOUND) {
    atomicAdd(counters[COUNTER_BLOCK_OPEN], 1u);  // left open for the seam stage
    return;
  }
  int lc = c_slot - slot_base;
  // Two active edges of one triangle may find it in the same iteration: the expansion that
  // claims the triangle's canonical edge (from its smallest local slot) keeps it.
  int x = la, y = lb, z = lc;
  if (lb < x && lb < lc) { x = lb; y = lc; z = la; }
  else if (lc < x && lc < lb) { x = lc; y = la; z = lb; }
  if (edge_insert(x, y) != 1) return;
  edge_insert(y, z);
  edge_insert(z, x);
  // Across blocks, only the block owning the smallest site id emits.
  int m = min(a, min(b, c));
  if (owner[m] == block) {
    uint at = atomicAdd(counters[COUNTER_TRIANGLES], 1u);
    if (int(at) < params.triangle_capacity) {
      triangles[3 * int(at)] = a;
      triangles[3 * int(at) + 1] = b;
      triangles[3 * int(at) + 2] = c;
    } else {
      atomicAdd(counters[COUNTER_OVERFLOW], 1u);
    }
  }
  // Outward edges c->b and a->c, unless their triangle is already known or they face out.
  if (predecessor[c] != b && !edge_known(lc, lb)) push_edge(next_parity, lc, lb);
  if (predecessor[a] != c && !edge_known(la, lc)) push_edge(next_parity, la, lc);
}

void main() {
  int block = params.first_block + int(gl_WorkGroupID.x);
  if (block >= params.block_count) return;
  int info = BLOCK_INFO_WORDS * block;
  Grid g;
  g.origin = params.origin;
  g.inv_width = params.inv_width;
  g.cells = params.cells;
  g.lo = ivec2(blocks[info + BLOCK_LO_X], blocks[info + BLOCK_LO_Y]);
  g.hi = ivec2(blocks[info + BLOCK_HI_X], blocks[info + BLOCK_HI_Y]);
  g.cell_base = blocks[info + BLOCK_CELL_BASE];
  slot_base = blocks[info + BLOCK_SLOT_BASE];
  int seed_slot = blocks[info + BLOCK_SEED_SLOT];
  hash_base = blocks[info + BLOCK_HASH_BASE];
  hash_capacity = blocks[info + BLOCK_HASH_CAPACITY];
  active_base = blocks[info + BLOCK_ACTIVE_BASE];
  active_capacity = blocks[info + BLOCK_ACTIVE_CAPACITY];
  uint tid = gl_LocalInvocationID.x;
  uint threads = gl_WorkGroupSize.x;
  loop_budget = LOOP_BUDGET;

  if (tid == 0u) {
    s_count = 0u;
    s_next = 0u;
    s_iterations = 0u;
    if (seed_slot >= 0) {
      int seed = local_ids[slot_base + seed_slot];
      int nearest, nearest_slot;
      int status = nearest_site(g, seed, nearest, nearest_slot);
      if (status == SEARCH_FOUND) {
        int ln = nearest_slot - slot_base;
        active_edges[active_base] = edge_key(seed_slot, ln);
        active_edges[active_base + 1] = edge_key(ln, seed_slot);
        s_count = 2u;
      } else if (status == SEARCH_DEFER) {
        atomicAdd(counters[COUNTER_DEFERRED], 1u);
      }
    }
  }
  memoryBarrierBuffer();
  memoryBarrierShared();
  barrier();

  int parity = 0;
  for (;;) {
    uint count = s_count;
    if (count == 0u) break;
    --loop_budget;
    for (uint i = tid; i < count; i += threads)
      expand(g, block, 1 - parity, active_edges[active_base + parity * active_capacity + int(i)]);
    memoryBarrierBuffer();
    memoryBarrierShared();
    barrier();
    if (tid == 0u) {
      if (s_next > uint(active_capacity)) atomicAdd(counters[COUNTER_BLOCK_ACTIVE_OVERFLOW], s_next - uint(active_capacity));
      s_count = min(s_next, uint(active_capacity));
      s_next = 0u;
      s_iterations += 1u;
    }
    memoryBarrierBuffer();
    memoryBarrierShared();
    barrier();
    parity = 1 - parity;
  }
  if (tid == 0u) atomicMax(counters[COUNTER_BLOCK_ITERATIONS], s_iterations);
}
