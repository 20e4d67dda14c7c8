#!/usr/bin/env bash
# Session 15 call 12: the quantile lookup's last columns counted at once (upper_index) against 9f31d06's loop: GPU-only, gaussian and kuzmin (quantile cells) and uniform, 2048^2 and 4096^2, two rounds alternated.
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $OUT/call12-lookup.jsonl; }
for round in 1 2; do
  timeout 150 .devrun/baseline/expanse_bench_cuda --sizes 2048,4096 --dists kuzmin,gaussian,uniform --reps 5 | tag loop-$round
  timeout 150 .devrun/expanse_bench_cuda --sizes 2048,4096 --dists kuzmin,gaussian,uniform --reps 5 | tag count-$round
done
python3 - $OUT/call12-lookup.jsonl <<'PY'
import json,sys
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  gpu=sum(v for k,v in s.items() if k not in ('upload','download'))
  print(f"{r['variant']:8} {r['distribution'][:5]:5} {r['side']:5} g {gpu:6.2f} st {s.get('stars',0):6.2f} d {r.get('deferred')} t {r.get('triangles')}")
PY
