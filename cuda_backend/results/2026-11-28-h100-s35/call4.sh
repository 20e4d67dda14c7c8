#!/usr/bin/env bash
# Session 35 call 4: why the merge's look back takes 0.5 ms on kuzmin 4096^2 (ncu on
# first_equal_kernel: speed of light, occupancy, warp states, memory; the SASS's stall samples).
set -u
bash bench/device/run-on-device.sh env > /dev/null 2>&1; rm -f $OUT/env.txt
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT
N=/usr/local/cuda/bin/ncu; B=.devrun/expanse_bench_cuda
timeout 200 $N --kernel-name regex:first_equal --launch-count 1 --section SpeedOfLight --section Occupancy --section WarpStateStats --section MemoryWorkloadAnalysis --section SchedulerStats --section LaunchStats $B --sizes 4096 --dists kuzmin --reps 1 2>&1 | grep -v '^{' | tee $OUT/call4-ncu-first-equal.txt | grep -E "Duration|Throughput|Occupancy|Warp Cycles|Stall|Issued|Eligible|Hit Rate|Registers|Active Warps|One or More" | head -50
timeout 200 $N --kernel-name regex:first_equal --launch-count 1 --set full --import-source no --page source --print-source sass --csv $B --sizes 4096 --dists kuzmin --reps 1 > $OUT/call4-ncu-sass.csv 2>/dev/null
echo "sass rc $?"; xz -T4 $OUT/call4-ncu-sass.csv
