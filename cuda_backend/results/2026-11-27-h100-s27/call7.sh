#!/usr/bin/env bash
# Session 27 call 7: with the walks compiled for their kind of grid (1ab934b's CUDA code), the
# settings whose trade-offs the kernels' registers decide, on uniform, gaussian and kuzmin 4096^2,
# two rounds alternated: the first pass's budget (2^10, 2^11 = default on quantile cells, 2^12),
# 2.5 sites a quantile cell, and the star kernels' blocks a multiprocessor (first phase, second
# phase, edge: 8,8,8 on quantile cells and 8,6,6 on uniform ones by default).
set -u
bash bench/device/run-on-device.sh env > $OUT/call7-env.txt 2>&1
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT
J=$OUT/call7-settings.jsonl
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $J; }
B=.devrun/expanse_bench_cuda
D="--sizes 4096 --dists uniform,gaussian,kuzmin --reps 5"
for round in 1 2; do
  timeout 100 $B $D | tag default
  EXPANSE_CUDA_FIRST_BUDGET=1024 timeout 100 $B --sizes 4096 --dists gaussian,kuzmin --reps 5 | tag first1024
  EXPANSE_CUDA_FIRST_BUDGET=4096 timeout 100 $B --sizes 4096 --dists gaussian,kuzmin --reps 5 | tag first4096
  timeout 100 $B --sizes 4096 --dists gaussian,kuzmin --reps 5 --sites-per-bucket 2.5 | tag spb2.5
  EXPANSE_CUDA_BLOCKS_PER_SM=8,6,8 timeout 100 $B $D | tag blocks868
  EXPANSE_CUDA_BLOCKS_PER_SM=8,8,8 timeout 100 $B $D | tag blocks888
  EXPANSE_CUDA_BLOCKS_PER_SM=8,6,6 timeout 100 $B $D | tag blocks866
  EXPANSE_CUDA_BLOCKS_PER_SM=6,8,8 timeout 100 $B --sizes 4096 --dists gaussian,kuzmin --reps 5 | tag blocks688
done
python3 - $J <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'], r['side'], r['variant'])].append('%.2f (stars %.2f, def %d)'%(g,s.get('stars',0),r['deferred']))
for k in sorted(d): print(*k, ' / '.join(d[k]))
PY
