#!/usr/bin/env bash
# Session 15 call 7: the first phase's retries beside the second phase with 1, 2, 4 blocks a multiprocessor (EXPANSE_CUDA_RETRY_BESIDE_BLOCKS) against none beside; GPU-only, alternated.
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $OUT/call7-beside-blocks.jsonl; }
for round in 1 2; do
  EXPANSE_CUDA_RETRY_BESIDE=0 timeout 150 .devrun/expanse_bench_cuda --sizes 2048,4096 --dists uniform,kuzmin,gaussian --reps 5 | tag b0-$round
  for k in 1 2 4; do
    EXPANSE_CUDA_RETRY_BESIDE_BLOCKS=$k timeout 150 .devrun/expanse_bench_cuda --sizes 2048,4096 --dists uniform,kuzmin,gaussian --reps 5 | tag k$k-$round
  done
done
python3 - $OUT/call7-beside-blocks.jsonl <<'PY'
import json,sys
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  gpu=sum(v for k,v in s.items() if k not in ('upload','download'))
  print(f"{r['variant']:5} {r['distribution'][:5]:5} {r['side']:5} g {gpu:6.2f} st {s.get('stars',0):6.2f} d {r.get('deferred')} t {r.get('triangles')}")
PY
