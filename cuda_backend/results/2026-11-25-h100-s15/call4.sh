#!/usr/bin/env bash
# Session 15 call 4: inboxes for 2 or 4 phases: the CUDA tests (two-phase cases added); GPU-only, phases 1, 2, 4.
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
timeout 200 .devrun/expanse_cuda_tests > $OUT/call4-tests.log 2>&1; echo "cuda tests rc $?"
grep -E "FAIL|passed|failed" $OUT/call4-tests.log | head -5
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $OUT/call4-phases.jsonl; }
for round in 1 2; do
  for p in 1 2 4; do
    EXPANSE_CUDA_PHASES=$p timeout 150 .devrun/expanse_bench_cuda --sizes 512,1024,2048,4096 --dists uniform,kuzmin,gaussian,grid --reps 5 | tag p$p-$round
  done
done
python3 - $OUT/call4-phases.jsonl <<'PY'
import json,sys
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  gpu=sum(v for k,v in s.items() if k not in ('upload','download'))
  print(f"{r['variant']:7} {r['distribution'][:5]:5} {r['side']:5} g {gpu:6.2f} st {s.get('stars',0):6.2f} d {r.get('deferred')} t {r.get('triangles')} p {r.get('predicates')}")
PY
