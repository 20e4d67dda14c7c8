#!/usr/bin/env bash
# Session 20 call 3: call 2 found the screen's walk 6.8 ms slower at 4096^2 uniform even with the
# screen off (its frame's six floats live across the candidate loop at the 64-register cap: the
# first-pass kernels' stacks grew), 7.9 ms with it on. Same bundle: does the screen pay where
# registers are not capped so hard (EXPANSE_CUDA_BLOCKS_PER_SM=6: 80 registers)? Against
# bb36602 at its default (8 blocks). Expected: no better than the baseline (6 blocks lost ~4% in
# session 11), but it says whether the screen's arithmetic helps once it does not spill.
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $OUT/call3-blocks6.jsonl; }
A="--sizes 4096 --dists uniform,kuzmin --reps 5"
for round in 1 2; do
  timeout 150 .devrun/baseline/expanse_bench_cuda $A | tag base8-$round
  EXPANSE_CUDA_BLOCKS_PER_SM=6 timeout 150 .devrun/baseline/expanse_bench_cuda $A | tag base6-$round
  EXPANSE_CUDA_BLOCKS_PER_SM=6 EXPANSE_CUDA_SCREEN=off timeout 150 .devrun/expanse_bench_cuda $A | tag off6-$round
  EXPANSE_CUDA_BLOCKS_PER_SM=6 timeout 150 .devrun/expanse_bench_cuda $A | tag screen6-$round
done
python3 - $OUT/call3-blocks6.jsonl <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'],r['side'],r['variant'].rsplit('-',1)[0])].append('%.2f (stars %.2f) def %d tri %d'%(g,s.get('stars',0),r['deferred'],r['triangles']))
for k in sorted(d): print(k, ' | '.join(d[k]))
PY
