#!/usr/bin/env bash
# Session 27 call 5: the final build (1ab934b's CUDA code): CUDA tests, the four sanitizers on
# their small cases, the conformance suite on CUDA; one more round of 4096^2 and 1024^2.
set -u
bash bench/device/run-on-device.sh env > $OUT/call5-env.txt 2>&1
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT
timeout 200 .devrun/expanse_cuda_tests > $OUT/call5-cuda-tests.log 2>&1; echo "cuda tests rc $?"; tail -1 $OUT/call5-cuda-tests.log
for tool in memcheck racecheck initcheck synccheck; do
  timeout 150 /usr/local/cuda/bin/compute-sanitizer --tool $tool --error-exitcode 9 .devrun/expanse_cuda_tests --small > /tmp/san.log 2>&1; echo "$tool rc $?"; tail -1 /tmp/san.log; (echo "=== $tool"; cat /tmp/san.log) >> $OUT/call5-sanitizers.log
done
timeout 150 .devrun/expanse_conformance --backend cuda > $OUT/call5-conformance.log 2>&1; echo "conformance rc $?"; tail -2 $OUT/call5-conformance.log
timeout 100 .devrun/expanse_bench_cuda --sizes 1024,4096 --dists uniform,gaussian,grid,kuzmin --reps 5 > $OUT/call5-final.jsonl
python3 - $OUT/call5-final.jsonl <<'PY'
import json,sys
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  print(r['distribution'], r['side'], '%.2f (stars %.2f, def %d, seam %.4f%%, h2h %.1f)'%(g,s.get('stars',0),r['deferred'],100*r.get('seam_share',0),r.get('host_to_host_ms',0)))
PY
