#!/usr/bin/env bash
# Session 16 call 4: the pooled walker (Walker::pooled, EXPANSE_CUDA_POOL=1) against the thread
# walker (the same build, and 88f976c's): triangles and deferred sites must match; CUDA tests
# and conformance on CUDA with pooling; GPU-only times at 1024^2 and 4096^2, two rounds.
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
EXPANSE_CUDA_POOL=1 timeout 60 .devrun/expanse_bench_cuda --sizes 1024 --dists uniform --reps 1 --no-pipeline > $OUT/call4-smoke.jsonl 2>&1; echo "smoke rc $?"
tail -c 400 $OUT/call4-smoke.jsonl
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $OUT/call4-pool.jsonl; }
for round in 1 2; do
  timeout 150 .devrun/baseline/expanse_bench_cuda --sizes 1024,4096 --dists uniform,kuzmin,gaussian,grid --reps 5 | tag base-$round
  timeout 150 .devrun/expanse_bench_cuda --sizes 1024,4096 --dists uniform,kuzmin,gaussian,grid --reps 5 | tag thread-$round
  EXPANSE_CUDA_POOL=1 timeout 150 .devrun/expanse_bench_cuda --sizes 1024,4096 --dists uniform,kuzmin,gaussian,grid --reps 5 | tag pool-$round
done
python3 - $OUT/call4-pool.jsonl <<'PY'
import json,sys
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  print(r['variant'], r['distribution'], r['side'], 'gpu-only %.2f'%g, 'stars %.2f'%s.get('stars',0), 'tri', r['triangles'], 'def', r['deferred'], 'pred', r['predicates'])
PY
EXPANSE_CUDA_POOL=1 timeout 200 .devrun/expanse_cuda_tests > $OUT/call4-cuda-tests-pool.log 2>&1; echo "cuda tests (pool) rc $?"; tail -3 $OUT/call4-cuda-tests-pool.log
EXPANSE_CUDA_POOL=1 EXPANSE_CUDA_PHASES=2 timeout 240 .devrun/expanse_conformance --backend cuda > $OUT/call4-conformance-pool.log 2>&1; echo "conformance (pool, two phases) rc $?"; tail -3 $OUT/call4-conformance-pool.log
