#!/usr/bin/env bash
# Session 23 call 6: the final code (the emit through StarView, its triangles staged; call 5's
# build with comments only changed). One round: 4096^2 four inputs, 512^2 and 2048^2 (uniform,
# kuzmin, grid); c3f9ffe (baseline/) at 4096^2 uniform and kuzmin on the same machine; CUDA tests,
# four sanitizers, conformance on CUDA.
set -u
bash bench/device/run-on-device.sh env >/dev/null
cp /dev/null $OUT/call6-final.jsonl
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT .devrun/baseline/COMMIT
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $OUT/call6-final.jsonl; }
timeout 150 .devrun/expanse_bench_cuda --sizes 4096 --dists uniform,gaussian,grid,kuzmin --reps 5 | tag head
timeout 90 .devrun/baseline/expanse_bench_cuda --sizes 4096 --dists uniform,kuzmin --reps 5 | tag base
timeout 100 .devrun/expanse_bench_cuda --sizes 512,2048 --dists uniform,kuzmin,grid --reps 7 | tag head
python3 - $OUT/call6-final.jsonl <<'PY'
import json,sys
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  print(r['variant'], r['distribution'], r['side'], '%.2f (stars %.2f, emit %.2f) h2h %.1f seam %.4f%% def %d tri %d'%(g,s.get('stars',0),s.get('emit',0),r.get('host_to_host_ms',0),100*r.get('seam_share',0),r['deferred'],r['triangles']))
PY
timeout 150 .devrun/expanse_cuda_tests > $OUT/call6-cuda-tests.log 2>&1; echo "cuda tests rc $?"; tail -1 $OUT/call6-cuda-tests.log
for tool in memcheck racecheck initcheck synccheck; do
  timeout 150 /usr/local/cuda/bin/compute-sanitizer --tool $tool --error-exitcode 9 .devrun/expanse_cuda_tests --small > /tmp/san.log 2>&1; echo "$tool rc $?"; tail -1 /tmp/san.log; (echo "=== $tool"; cat /tmp/san.log) >> $OUT/call6-sanitizers.log
done
timeout 150 .devrun/expanse_conformance --backend cuda > $OUT/call6-conformance.log 2>&1; echo "conformance rc $?"; tail -2 $OUT/call6-conformance.log
