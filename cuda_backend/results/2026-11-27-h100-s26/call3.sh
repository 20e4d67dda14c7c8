#!/usr/bin/env bash
# Session 26 call 3: why kuzmin's second phase costs 1.8x uniform's for as many searching sites
# (call 1's timelines: 10.7 against 5.85 ms, 4.58 M against 4.61 M sites): ncu's full set on the
# second phase's walks (star_list_kernel reading inboxes) and on the first phase's star_kernel,
# 4096^2 uniform and kuzmin, unpipelined. (The first run's name filter for the second phase
# matched nothing; call3-ncu.txt holds its kuzmin first phase. This is the second run.)
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT
B=.devrun/expanse_bench_cuda
N=/usr/local/cuda/bin/ncu
for dist in uniform kuzmin; do
  echo "=== ncu phase 1 $dist" >> $OUT/call3b-ncu.txt
  timeout 200 $N --kernel-name-base demangled -k regex:'star_list_kernel<.*\(bool\)1, \(bool\)1, \(bool\)0>' --launch-skip 1 --launch-count 1 --set full \
    $B --sizes 4096 --dists $dist --reps 1 --no-pipeline >> $OUT/call3b-ncu.txt 2>&1; echo "ncu phase 1 $dist rc $?"
done
grep -E "===|star_list_kernel|star_kernel|Duration|Executed Instructions  |Warp Cycles Per Issued|Avg. Active Threads Per Warp|L1/TEX Hit Rate|L2 Hit Rate|DRAM Throughput|Executed Ipc Active|Achieved Occupancy|Registers Per|No Eligible|Issue Slots Busy|Branch Instructions Ratio|Avg. Divergent" $OUT/call3b-ncu.txt | cut -c1-160 | head -90
