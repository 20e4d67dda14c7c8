#!/usr/bin/env bash
# Session 19 call 11 (review): triangle_index ends in owned_triangle_index (the same offset and
# owned bits, one expression instead of two); the CUDA tests, memcheck and the conformance suite
# on CUDA on that build, and 4096^2 uniform and kuzmin once to see the emit unchanged.
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT
timeout 90 .devrun/expanse_bench_cuda --sizes 4096 --dists uniform,kuzmin --reps 5 > $OUT/call11-bench.jsonl
python3 - $OUT/call11-bench.jsonl <<'PY'
import json,sys
for l in open(sys.argv[1]):
  r=json.loads(l); s=r['pipeline_device_stages_ms']
  print(r['distribution'], r['side'], 'gpu %.2f emit %.2f audit %.2f def %d tri %d' % (sum(v for k,v in s.items() if k not in ('upload','download')), s['emit'], s['audit'], r['deferred'], r['triangles']))
PY
timeout 90 .devrun/expanse_cuda_tests > $OUT/call11-cuda-tests.log 2>&1; echo "cuda tests rc $?"; tail -1 $OUT/call11-cuda-tests.log
timeout 90 /usr/local/cuda/bin/compute-sanitizer --tool memcheck --error-exitcode 9 .devrun/expanse_cuda_tests --small > $OUT/call11-memcheck.log 2>&1; echo "memcheck rc $?"; tail -1 $OUT/call11-memcheck.log
timeout 150 .devrun/expanse_conformance --backend cuda > $OUT/call11-conformance.log 2>&1; echo "conformance rc $?"; tail -2 $OUT/call11-conformance.log
