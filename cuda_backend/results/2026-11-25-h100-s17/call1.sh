#!/usr/bin/env bash
# Session 17 call 1: 6e8dc09 (session 16's last: uniform cells at 3.5 sites, the bucket fix) as
# it stands. The full sweep 32^2-4096^2, four inputs (GPU-only, host to host, seam share); CUDA
# tests; conformance on CUDA with one and two phases; the four compute-sanitizer tools.
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
nvidia-smi --query-gpu=name,clocks.sm,clocks.max.sm,temperature.gpu,power.draw --format=csv
uptime
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $OUT/call1-sweep.jsonl; }
timeout 200 .devrun/expanse_bench_cuda --sizes 32,64,128,256,512,1024,2048,4096 --dists uniform,kuzmin,gaussian,grid --reps 5 | tag head-1
timeout 120 .devrun/expanse_bench_cuda --sizes 512,4096 --dists uniform,kuzmin,gaussian,grid --reps 5 | tag head-2
python3 - $OUT/call1-sweep.jsonl <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'],r['side'])].append('%.2f (stars %.2f bucket %.2f) h2h %.1f def %d seam %.5f'%(g,s.get('stars',0),s.get('bucket',0),r.get('host_to_host_ms',0),r['deferred'],r.get('seam_share',0)))
for k in sorted(d): print(k, ' | '.join(d[k]))
PY
timeout 200 .devrun/expanse_cuda_tests > $OUT/call1-cuda-tests.log 2>&1; echo "cuda tests rc $?"; tail -1 $OUT/call1-cuda-tests.log
timeout 200 .devrun/expanse_conformance --backend cuda > $OUT/call1-conformance.log 2>&1; echo "conformance rc $?"; tail -2 $OUT/call1-conformance.log
EXPANSE_CUDA_PHASES=2 timeout 200 .devrun/expanse_conformance --backend cuda >> $OUT/call1-conformance.log 2>&1; echo "conformance (two phases) rc $?"; tail -2 $OUT/call1-conformance.log
for tool in memcheck racecheck initcheck synccheck; do
  timeout 150 /usr/local/cuda/bin/compute-sanitizer --tool $tool --error-exitcode 9 .devrun/expanse_cuda_tests --small > $OUT/call1-sanitizer-$tool.log 2>&1; echo "$tool rc $?"; tail -1 $OUT/call1-sanitizer-$tool.log
done
