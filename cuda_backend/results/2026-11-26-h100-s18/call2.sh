#!/usr/bin/env bash
# Session 18 call 2: where kuzmin's first phase spends the time uniform's does not. ncu source
# counters of the first phase's kernel (star_kernel, phase 0) at 4096^2, kuzmin then uniform, in one
# call on call 1's build (its default path is HEAD's), tabulated by source line (session 16's source_lines.py; it ran from a copy in this folder, since removed).
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
NCU=/usr/local/cuda/bin/ncu
cat .devrun/COMMIT
for d in kuzmin uniform; do
  timeout 200 $NCU --kernel-name regex:"star_kernel" --launch-count 1 --section SourceCounters --section SpeedOfLight \
    --import-source yes -o /tmp/phase0-$d -f .devrun/expanse_bench_cuda --sizes 4096 --dists $d --reps 1 --no-pipeline > $OUT/call2-ncu-$d.log 2>&1; echo "ncu $d rc $?"
  $NCU -i /tmp/phase0-$d.ncu-rep --page source --csv --print-source cuda,sass > $OUT/call2-cuda-sass-$d.csv 2>&1; echo "export $d rc $?"
  $NCU -i /tmp/phase0-$d.ncu-rep --page details --csv >> $OUT/call2-ncu-$d.log 2>&1
  xz -6 $OUT/call2-cuda-sass-$d.csv
  python3 cuda_backend/results/2026-11-25-h100-s16/source_lines.py $OUT/call2-cuda-sass-$d.csv.xz | head -40
done
