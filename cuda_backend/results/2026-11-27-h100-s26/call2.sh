#!/usr/bin/env bash
# Session 26 call 2: with the first phase's retries beside the second phase (7134e5c), the
# settings whose trade-offs that moves, on kuzmin and gaussian 4096^2, two rounds alternated:
# the first pass's budget (2^10, 2^11 = default, 2^12), sites per quantile cell (2 = default,
# 2.5, 3), the star kernels' blocks per multiprocessor (8,8,8 = default, 8,6,8).
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT
J=$OUT/call2-settings.jsonl
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $J; }
B=.devrun/expanse_bench_cuda
D="--sizes 4096 --dists gaussian,kuzmin --reps 5"
for round in 1 2; do
  timeout 100 $B $D | tag default
  EXPANSE_CUDA_FIRST_BUDGET=1024 timeout 100 $B $D | tag first1024
  EXPANSE_CUDA_FIRST_BUDGET=4096 timeout 100 $B $D | tag first4096
  timeout 100 $B $D --sites-per-bucket 2.5 | tag spb2.5
  timeout 100 $B $D --sites-per-bucket 3 | tag spb3
  EXPANSE_CUDA_BLOCKS_PER_SM=8,6,8 timeout 100 $B $D | tag blocks868
done
python3 - $J <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'], r['side'], r['variant'])].append('%.2f (stars %.2f, bucket %.2f, def %d)'%(g,s.get('stars',0),s.get('bucket',0),r['deferred']))
for k in sorted(d): print(*k, ' / '.join(d[k]))
PY
