#!/usr/bin/env bash
# Session 16 call 2: the even phase's instructions by source line (ncu source counters: warp
# instructions, thread instructions, so lanes active a line), to see which loop level costs.
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
NCU=/usr/local/cuda/bin/ncu
$NCU --version | tail -1
for k in 0 1; do
timeout 250 $NCU --kernel-name regex:"star_kernel" --launch-skip $k --launch-count 1 --section SourceCounters --section InstructionStats \
  --import-source yes -o $OUT/call2-phase$k -f .devrun/expanse_bench_cuda --sizes 4096 --dists uniform --reps 1 --no-pipeline > $OUT/call2-ncu-$k.log 2>&1; echo "ncu $k rc $?"
$NCU -i $OUT/call2-phase$k.ncu-rep --page source --csv --print-source cuda > $OUT/call2-source-phase$k.csv 2>$OUT/call2-source-err$k.txt; echo "export rc $?"
ls -la $OUT/call2-source-phase$k.csv
head -c 600 $OUT/call2-source-phase$k.csv
done
rm -f $OUT/*.ncu-rep
