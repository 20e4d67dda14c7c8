#!/usr/bin/env bash
# Session 18 call 5 (run at the start of session 19, 2026-11-26, on 8f27b71):
# the final build (the ends-first block order the default on quantile cells)
# against the cell order (EXPANSE_CUDA_BLOCK_ORDER=cells), 2048^2 and 4096^2, four inputs, two
# rounds alternated; CUDA tests; the four sanitizers; conformance on CUDA last (what the device
# time left allows).
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $OUT/call5-final.jsonl; }
B=".devrun/expanse_bench_cuda --sizes 2048,4096 --dists uniform,kuzmin,gaussian,grid --reps 5"
for round in 1 2; do
  timeout 60 $B | tag default-$round
  EXPANSE_CUDA_BLOCK_ORDER=cells timeout 60 $B | tag cells-$round
done
python3 - $OUT/call5-final.jsonl <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'],r['side'],r['variant'].split('-')[0])].append('%.2f (stars %.2f) h2h %.1f def %d seam %.6f'%(g,s.get('stars',0),r.get('host_to_host_ms',0),r['deferred'],r.get('seam_share',0)))
for k in sorted(d): print(k, ' | '.join(d[k]))
PY
timeout 60 .devrun/expanse_cuda_tests > $OUT/call5-cuda-tests.log 2>&1; echo "cuda tests rc $?"; tail -1 $OUT/call5-cuda-tests.log
for tool in memcheck initcheck synccheck racecheck; do
  timeout 60 /usr/local/cuda/bin/compute-sanitizer --tool $tool --error-exitcode 9 .devrun/expanse_cuda_tests --small > /tmp/san.log 2>&1; echo "$tool rc $?"; tail -1 /tmp/san.log; (echo "=== $tool"; cat /tmp/san.log) >> $OUT/call5-sanitizers.log
done
timeout 150 .devrun/expanse_conformance --backend cuda > $OUT/call5-conformance.log 2>&1; echo "conformance rc $?"; tail -2 $OUT/call5-conformance.log
