#!/usr/bin/env bash
# Session 16 call 6: why the pooled walker (call 4, call4-pooled.diff applied again) lost: its
# first phase under ncu (instructions, lanes, pipes) and its instructions by source line.
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
NCU=/usr/local/cuda/bin/ncu
EXPANSE_CUDA_POOL=1 timeout 250 $NCU --kernel-name regex:"star_kernel" --launch-count 1 --section SourceCounters --section InstructionStats \
  --section WarpStateStats --section ComputeWorkloadAnalysis --section SpeedOfLight --import-source yes -o $OUT/call6-pooled -f \
  .devrun/expanse_bench_cuda --sizes 4096 --dists uniform --reps 1 --no-pipeline > $OUT/call6-ncu.log 2>&1; echo "ncu rc $?"
$NCU -i $OUT/call6-pooled.ncu-rep --page details > $OUT/call6-details.txt 2>&1
$NCU -i $OUT/call6-pooled.ncu-rep --page source --csv --print-source cuda,sass > $OUT/call6-cuda-sass.csv 2>&1; echo "export rc $?"
grep -E "Duration|Executed Instructions |Avg. Active Threads|Issue Slots Busy|Executed Ipc Active" $OUT/call6-details.txt
xz -9 $OUT/call6-cuda-sass.csv
rm -f $OUT/*.ncu-rep
