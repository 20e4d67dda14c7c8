#!/usr/bin/env bash
# Session 30 call 2: what the star stage's last kernel (the main stream's retry, kuzmin's 1.3 ms
# tail after the second phase) waits on: ncu on every star_retry_kernel of one kuzmin 4096^2 run
# (the edge's retry, the first phase's retry, the last retry; warm-up and one rep), S (the bundle's
# build) and the baseline.
set -u
python3 -c "import tarfile; tarfile.open('.devrun/bundle.tar.xz').extractall('.devrun')"
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
export LD_LIBRARY_PATH=$PWD/.devrun/lib PATH=/usr/local/cuda/bin:$PATH; which ncu
cat .devrun/COMMIT; nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
B=.devrun/expanse_bench_cuda O=.devrun/baseline/expanse_bench_cuda
for b in S:$B base:$O; do
  echo "== ncu kuzmin ${b%%:*}"
  timeout 250 ncu -k regex:star_retry_kernel -c 6 --section SpeedOfLight --section Occupancy --section WarpStateStats \
    --section LaunchStats --section SchedulerStats \
    --metrics sm__cycles_active.max,sm__cycles_active.avg,gpc__cycles_elapsed.max,smsp__warps_launched.sum,smsp__inst_executed.sum \
    ${b#*:} --sizes 4096 --dists kuzmin --reps 1 > $OUT/call2-ncu-raw-${b%%:*}.txt 2>&1; grep -E "star_retry_kernel|Duration|SM Busy|Compute \(SM\) Throughput|Memory Throughput|Achieved Occupancy|sm__cycles_active|gpc__cycles|warps_launched|inst_executed|Stall|Warp Cycles Per Issued|Active Warps Per Scheduler|Eligible|Issued Warp|No Eligible|Grid Size" $OUT/call2-ncu-raw-${b%%:*}.txt; tail -3 $OUT/call2-ncu-raw-${b%%:*}.txt
done 2>&1 | tee $OUT/call2-ncu.txt
