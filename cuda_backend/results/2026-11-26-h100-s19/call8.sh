#!/usr/bin/env bash
# Session 19 call 8: where the preparation and bucket stages' time goes, kernel by kernel (ncu's
# gpu__time_duration, every kernel but the star walks and the emit), 4096^2 kuzmin and uniform,
# one repetition after the warm-up (backend alone, then the pipeline).
# (Its inline summary below failed on ncu's output, whose CSV rows come mixed with the benchmark's own;
# kernel_times.py reads the two files instead.)
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT
NCU=/usr/local/cuda/bin/ncu
for d in kuzmin uniform; do
  timeout 250 $NCU --metrics gpu__time_duration.sum --csv \
    --kernel-name regex:'^(?!star_|emit_|audit|link_open)' \
    .devrun/expanse_bench_cuda --sizes 4096 --dists $d --reps 1 > $OUT/call8-ncu-$d.csv 2> $OUT/call8-ncu-$d.log
  echo "$d rc $?"
done
python3 - $OUT/call8-ncu-kuzmin.csv $OUT/call8-ncu-uniform.csv <<'PY'
import csv, sys, collections
for path in sys.argv[1:]:
  rows = [r for r in csv.reader(open(path)) if len(r) > 10]
  if not rows: print(path, 'no rows'); continue
  h = rows[0]; ki = h.index('Kernel Name'); vi = h.index('Metric Value'); ui = h.index('Metric Unit')
  seq = []
  for r in rows[1:]:
    v = float(r[vi].replace(',', '')); u = r[ui]
    ms = v / 1e6 if u == 'nsecond' else v / 1e3 if u == 'usecond' else v if u == 'msecond' else v / 1e9
    seq.append((r[ki].split('(')[0][:60], ms))
  # the pipeline's timed repetition: from the last launch of the preparation's first kernel on
  n = len(seq)
  starts = [i for i, (k, _) in enumerate(seq) if 'short_key_kernel' in k or 'morton_kernel' in k]
  tail = seq[starts[-1]:] if starts else seq[3 * n // 4:]
  agg = collections.OrderedDict()
  for k, ms in tail: agg[k] = agg.get(k, 0) + ms
  print('==', path.split('/')[-1], 'launches', n, 'from the last preparation', len(tail), 'ms %.3f' % sum(agg.values()))
  for k, ms in agg.items(): print('  %-60s %.3f' % (k, ms))
PY
