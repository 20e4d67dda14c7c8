#!/usr/bin/env bash
# Session 15 call 6: the first phase's retries beside the second phase (on the edge stream): the CUDA tests, memcheck and racecheck on the small cases; GPU-only with EXPANSE_CUDA_RETRY_BESIDE=0 and 1, alternated.
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
timeout 200 .devrun/expanse_cuda_tests > $OUT/call6-tests.log 2>&1; echo "cuda tests rc $?"
grep -E "FAIL|PASSED" $OUT/call6-tests.log | head -5
for tool in memcheck racecheck; do
  timeout 240 /usr/local/cuda/bin/compute-sanitizer --tool $tool --error-exitcode 9 .devrun/expanse_cuda_tests --small > $OUT/call6-sanitizer-$tool.log 2>&1; echo "$tool rc $?"; tail -1 $OUT/call6-sanitizer-$tool.log
done
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $OUT/call6-beside.jsonl; }
for round in 1 2; do
  for b in 0 1; do
    EXPANSE_CUDA_RETRY_BESIDE=$b timeout 150 .devrun/expanse_bench_cuda --sizes 512,1024,2048,4096 --dists uniform,kuzmin,gaussian,grid --reps 5 | tag b$b-$round
  done
done
python3 - $OUT/call6-beside.jsonl <<'PY'
import json,sys
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  gpu=sum(v for k,v in s.items() if k not in ('upload','download'))
  print(f"{r['variant']:5} {r['distribution'][:5]:5} {r['side']:5} g {gpu:6.2f} st {s.get('stars',0):6.2f} d {r.get('deferred')} t {r.get('triangles')}")
PY
