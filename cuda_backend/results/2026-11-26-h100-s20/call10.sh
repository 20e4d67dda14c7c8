#!/usr/bin/env bash
# Session 20 call 10: the code at HEAD (call 9's with quantile cells back at 8 blocks in every
# group, as bb36602 runs them). Expected: uniform as call 9's 'new' rows, quantile inputs as its
# 'base' rows. One round: 4096^2 every distribution, 512^2 uniform and kuzmin; CUDA tests,
# memcheck, conformance on CUDA.
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $OUT/call10-head.jsonl; }
timeout 200 .devrun/expanse_bench_cuda --sizes 4096 --dists uniform,gaussian,grid,kuzmin --reps 5 | tag head-1
timeout 60 .devrun/expanse_bench_cuda --sizes 512 --dists uniform,kuzmin --reps 9 | tag head-1
python3 - $OUT/call10-head.jsonl <<'PY'
import json,sys
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  print(r['distribution'], r['side'], '%.2f (stars %.2f) h2h %.1f seam %.4f%% def %d tri %d'%(g,s.get('stars',0),r.get('host_to_host_ms',0),100*r.get('seam_share',0),r['deferred'],r['triangles']))
PY
timeout 90 .devrun/expanse_cuda_tests > $OUT/call10-cuda-tests.log 2>&1; echo "cuda tests rc $?"; tail -1 $OUT/call10-cuda-tests.log
timeout 90 /usr/local/cuda/bin/compute-sanitizer --tool memcheck --error-exitcode 9 .devrun/expanse_cuda_tests --small > $OUT/call10-memcheck.log 2>&1; echo "memcheck rc $?"; tail -1 $OUT/call10-memcheck.log
timeout 150 .devrun/expanse_conformance --backend cuda > $OUT/call10-conformance.log 2>&1; echo "conformance rc $?"; tail -2 $OUT/call10-conformance.log
