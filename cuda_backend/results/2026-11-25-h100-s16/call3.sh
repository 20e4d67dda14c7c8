#!/usr/bin/env bash
# Session 16 call 3: call 2 again, the source counters exported per SASS instruction with their
# CUDA lines (call 2's export printed the source without metrics).
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
NCU=/usr/local/cuda/bin/ncu
timeout 250 $NCU --kernel-name regex:"star_kernel" --launch-count 1 --section SourceCounters \
  --import-source yes -o $OUT/call3-phase0 -f .devrun/expanse_bench_cuda --sizes 4096 --dists uniform --reps 1 --no-pipeline > $OUT/call3-ncu.log 2>&1; echo "ncu rc $?"
$NCU -i $OUT/call3-phase0.ncu-rep --page source --csv --print-source cuda,sass > $OUT/call3-cuda-sass.csv 2>&1; echo "export1 rc $?"
$NCU -i $OUT/call3-phase0.ncu-rep --page source --csv --print-source sass > $OUT/call3-sass.csv 2>&1; echo "export2 rc $?"
ls -la $OUT
head -c 1500 $OUT/call3-cuda-sass.csv; echo; head -c 1500 $OUT/call3-sass.csv
xz -9 $OUT/call3-*.csv
rm -f $OUT/*.ncu-rep
