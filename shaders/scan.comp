#version 450
// Inclusive prefix sum of int32 in place, over tiles of 4 x workgroup size elements, as a
// hierarchy the host records level by level (vulkan_backend.cpp, record_scan):
//   SCAN_PASS_TILES: each workgroup scans its tile and stores the tile's total in the next level;
//   SCAN_PASS_ADD:   each tile after the first adds the scanned total of the tiles before it.
// Level 0 is the `data` buffer; higher levels live in `sums` at offsets given by the host.
// Only workgroup barriers and shared memory: no subgroup operations, so nothing depends on the
// subgroup size (8 on lavapipe, 32 on NVIDIA).
#extension GL_GOOGLE_include_directive : require

#include "host_device.h"

layout(local_size_x_id = 0) in;
const int PER_THREAD = SCAN_PER_THREAD;

layout(std430, set = 0, binding = 0) buffer Data { int data[]; };
layout(std430, set = 0, binding = 1) buffer Sums { int sums[]; };

layout(push_constant) uniform Push { ScanParams params; };

shared int thread_totals[gl_WorkGroupSize.x];
const int WORKGROUP = int(gl_WorkGroupSize.x);

int load(int i) { return params.level_in_sums != 0 ? sums[params.offset + i] : data[params.offset + i]; }
void store(int i, int v) {
  if (params.level_in_sums != 0)
    sums[params.offset + i] = v;
  else
    data[params.offset + i] = v;
}

void main() {
  const int tile = params.first_tile + int(gl_WorkGroupID.x);
  const int local = int(gl_LocalInvocationID.x);
  const int base = tile * WORKGROUP * PER_THREAD + local * PER_THREAD;
  if (params.pass == SCAN_PASS_ADD) {
    if (tile == 0) return;
    const int before = sums[params.sums_offset + tile - 1];
    for (int k = 0; k < PER_THREAD; ++k)
      if (base + k < params.count) store(base + k, load(base + k) + before);
    return;
  }
  int values[PER_THREAD];
  int running = 0;
  for (int k = 0; k < PER_THREAD; ++k) {
    running += base + k < params.count ? load(base + k) : 0;
    values[k] = running;
  }
  thread_totals[local] = running;
  barrier();
  // Hillis-Steele over the threads' totals: log2(WORKGROUP) steps, every thread at every barrier.
  for (int step = 1; step < WORKGROUP; step <<= 1) {
    const int add = local >= step ? thread_totals[local - step] : 0;
    barrier();
    thread_totals[local] += add;
    barrier();
  }
  const int before = local > 0 ? thread_totals[local - 1] : 0;
  for (int k = 0; k < PER_THREAD; ++k)
    if (base + k < params.count) store(base + k, values[k] + before);
  if (local == WORKGROUP - 1) sums[params.sums_offset + tile] = thread_totals[local];
}
