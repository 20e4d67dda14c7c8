#version 450
// The host audit's first check (seam/adjacency_audit.cpp) where the adjacency was made, so the
// host does not read all of it back at random (336 ms at 4096^2 on the H100's host): every link
// leads to a triangle that holds the same edge the other way round and links back across it.
// A missing link on an edge that is not an outer hull edge (y's hull predecessor is not x) is
// an open edge: counted and its slot (3 t + k) listed, for the host's second check, which
// needs only the few open edges (the seam). One invocation per triangle; triangles in SiteSet ids (after
// bucket.comp's restore pass), and `predecessor` is hull.predecessor in SiteSet ids.
#extension GL_GOOGLE_include_directive : require

#include "host_device.h"

layout(local_size_x_id = 0) in;

layout(std430, set = 0, binding = 0) readonly buffer Triangles { int triangles[]; };
layout(std430, set = 0, binding = 1) readonly buffer Neighbors { int neighbors[]; };
layout(std430, set = 0, binding = 2) readonly buffer Predecessor { int predecessor[]; };
layout(std430, set = 0, binding = 3) writeonly buffer OpenSlots { int open_slots[]; };
// star.comp's counters: [0] triangles written; here [10] bad links, [11] open edges,
// [12] open edges beyond open_capacity (not listed)
layout(std430, set = 0, binding = 4) buffer Counters { uint counters[]; };

layout(push_constant) uniform Push { AuditParams params; };

void main() {
  const int t = params.first + int(gl_GlobalInvocationID.x);
  const int count = int(min(counters[COUNTER_TRIANGLES], uint(params.triangle_capacity)));
  if (t >= count) return;
  uint bad = 0u;
  for (int k = 0; k < 3; ++k) {
    const int x = triangles[3 * t + (k + 1) % 3];
    const int y = triangles[3 * t + (k + 2) % 3];
    const int u = neighbors[3 * t + k];
    if (u == -1) {
      if (predecessor[y] != x) {
        const uint at = atomicAdd(counters[COUNTER_OPEN_EDGES], 1u);
        if (int(at) < params.open_capacity)
          open_slots[int(at)] = 3 * t + k;
        else
          atomicAdd(counters[COUNTER_OPEN_OVERFLOW], 1u);
      }
      continue;
    }
    if (u < 0 || u >= count) {
      ++bad;
      continue;
    }
    int j = 0;
    while (j < 3 && !(triangles[3 * u + (j + 1) % 3] == y && triangles[3 * u + (j + 2) % 3] == x)) ++j;
    if (j == 3 || neighbors[3 * u + j] != t) ++bad;
  }
  if (bad != 0u) atomicAdd(counters[COUNTER_BAD_LINKS], bad);
}
