#!/usr/bin/env bash
# Session 23 call 1: where the emit's 3.2 ms goes (4096^2 uniform, GPU-only; session 22 call 10:
# emit 3.19 ms, the stage after the stars). ncu, full set, one launch each of the two emit
# kernels and the audit, after the warm-up's; the baseline build c3f9ffe.
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT
B=.devrun/expanse_bench_cuda
timeout 300 /usr/local/cuda/bin/ncu --kernel-name regex:"emit_|audit_kernel" --launch-skip 3 --launch-count 3 --set full \
  $B --sizes 4096 --dists uniform --reps 1 --no-pipeline > $OUT/call1-ncu-emit.txt 2>&1; echo "ncu rc $?"
grep -E "emit_|audit_kernel|Duration|Memory Throughput|DRAM Throughput|Compute \(SM\)|Achieved Occupancy|Registers Per|L2 Hit|L1/TEX Hit|Warp Cycles Per Issued|One or More Eligible|excessive" $OUT/call1-ncu-emit.txt | cut -c1-200 | head -60
