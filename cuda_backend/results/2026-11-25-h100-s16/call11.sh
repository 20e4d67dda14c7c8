#!/usr/bin/env bash
# Session 16 call 11: uniform cells at 1.75 x sites_per_bucket for non-integer sites
# (kUniformCellsScale) against a710cd0 (88f976c's code), alternated, two rounds, 512^2-4096^2,
# four inputs (GPU-only and host to host); CUDA tests; conformance on CUDA, one and two phases;
# compute-sanitizer memcheck and racecheck on the small cases.
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $OUT/call11-cells.jsonl; }
for round in 1 2; do
  timeout 150 .devrun/baseline/expanse_bench_cuda --sizes 512,1024,2048,4096 --dists uniform,kuzmin,gaussian,grid --reps 5 | tag base-$round
  timeout 150 .devrun/expanse_bench_cuda --sizes 512,1024,2048,4096 --dists uniform,kuzmin,gaussian,grid --reps 5 | tag cells-$round
done
python3 - $OUT/call11-cells.jsonl <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'],r['side'],r['variant'].split('-')[0])].append('%.2f (%.2f) h2h %.1f tri %d def %d seam %.5f'%(g,s.get('stars',0),r.get('host_to_host_ms',0),r['triangles'],r['deferred'],r.get('seam_share',0)))
for k in sorted(d): print(k, ' | '.join(d[k]))
PY
timeout 200 .devrun/expanse_cuda_tests > $OUT/call11-cuda-tests.log 2>&1; echo "cuda tests rc $?"; tail -1 $OUT/call11-cuda-tests.log
timeout 200 .devrun/expanse_conformance --backend cuda > $OUT/call11-conformance.log 2>&1; echo "conformance rc $?"; tail -2 $OUT/call11-conformance.log
EXPANSE_CUDA_PHASES=2 timeout 200 .devrun/expanse_conformance --backend cuda > $OUT/call11-conformance-two-phases.log 2>&1; echo "conformance (two phases) rc $?"; tail -2 $OUT/call11-conformance-two-phases.log
for tool in memcheck racecheck; do
  timeout 150 /usr/local/cuda/bin/compute-sanitizer --tool $tool --error-exitcode 9 .devrun/expanse_cuda_tests --small > $OUT/call11-sanitizer-$tool.log 2>&1; echo "$tool rc $?"; tail -1 $OUT/call11-sanitizer-$tool.log
done
