#!/usr/bin/env bash
# Session 20 call 4: the star kernels' tuning knobs again, on bb36602's code (the screen reverted;
# .devrun/baseline/ is that build). Call 3 found 6 blocks a multiprocessor (80 registers) 1.4%
# faster than 8 at 4096^2 uniform (38.6 against 39.15 ms) where session 11 had found 8 faster by
# 4%; kuzmin lost 5% at 6. Here: 6 against 8 at 512^2 .. 4096^2 uniform; and at 4096^2 uniform
# and kuzmin the first pass's budget, the edge stream's depth and the interior retry budget,
# one at a time around the defaults. Two rounds alternated.
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
B=.devrun/baseline/expanse_bench_cuda
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $OUT/call4-knobs.jsonl; }
S="--sizes 512,1024,2048 --dists uniform --reps 9"
U="--sizes 4096 --dists uniform --reps 5"
K="--sizes 4096 --dists kuzmin --reps 5"
for round in 1 2; do
  timeout 60 $B $S | tag blocks8-$round
  EXPANSE_CUDA_BLOCKS_PER_SM=6 timeout 60 $B $S | tag blocks6-$round
  for v in "" "EXPANSE_CUDA_BLOCKS_PER_SM=6" "EXPANSE_CUDA_FIRST_BUDGET=512" "EXPANSE_CUDA_FIRST_BUDGET=2048" \
           "EXPANSE_CUDA_EDGE_DEPTH=0" "EXPANSE_CUDA_EDGE_DEPTH=2" "EXPANSE_CUDA_RETRY_BUDGET=4096" "EXPANSE_CUDA_RETRY_BUDGET=16384"; do
    env $v timeout 60 $B $U | tag "u${v:-default}-$round"
  done
  for v in "" "EXPANSE_CUDA_FIRST_BUDGET=2048" "EXPANSE_CUDA_FIRST_BUDGET=8192" "EXPANSE_CUDA_EDGE_DEPTH=0" \
           "EXPANSE_CUDA_EDGE_DEPTH=2" "EXPANSE_CUDA_RETRY_BUDGET=4096" "EXPANSE_CUDA_RETRY_BUDGET=16384"; do
    env $v timeout 60 $B $K | tag "k${v:-default}-$round"
  done
done
python3 - $OUT/call4-knobs.jsonl <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'],r['side'],r['variant'].rsplit('-',1)[0])].append('%.2f (stars %.2f) def %d'%(g,s.get('stars',0),r['deferred']))
for k in sorted(d): print(k, ' | '.join(d[k]))
PY
