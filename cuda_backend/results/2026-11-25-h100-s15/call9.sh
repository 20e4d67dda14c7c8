#!/usr/bin/env bash
# Session 15 call 9: the first pass's budget on quantile cells with two phases: 2^11 (default) against 2^12 and 2^13, kuzmin and gaussian, 2048^2 and 4096^2, two rounds alternated (GPU-only).
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $OUT/call9-first-budget.jsonl; }
for round in 1 2; do
  for b in 2048 4096 8192; do
    EXPANSE_CUDA_FIRST_BUDGET=$b timeout 150 .devrun/expanse_bench_cuda --sizes 2048,4096 --dists kuzmin,gaussian --reps 5 | tag f$b-$round
  done
done
python3 - $OUT/call9-first-budget.jsonl <<'PY'
import json,sys
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  gpu=sum(v for k,v in s.items() if k not in ('upload','download'))
  print(f"{r['variant']:7} {r['distribution'][:5]:5} {r['side']:5} g {gpu:6.2f} st {s.get('stars',0):6.2f} d {r.get('deferred')} t {r.get('triangles')}")
PY
