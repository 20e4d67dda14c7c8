#!/usr/bin/env bash
# Session 30 call 11: after the review (the low stream's join by the edge retry's own event,
# re-recorded): CUDA tests, the conformance suite on CUDA, memcheck and synccheck on the small
# cases, and one round of 4096^2 uniform and kuzmin.
set -u
python3 -c "import tarfile; tarfile.open('.devrun/bundle.tar.xz').extractall('.devrun')"
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT; nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
timeout 150 .devrun/expanse_cuda_tests > $OUT/call11-cuda-tests.log 2>&1; echo "cuda tests rc $?"; grep -E "^FAIL" $OUT/call11-cuda-tests.log | head; tail -1 $OUT/call11-cuda-tests.log
timeout 170 .devrun/expanse_conformance --backend cuda > $OUT/call11-conformance.log 2>&1; echo "conformance rc $?"; tail -2 $OUT/call11-conformance.log
for tool in memcheck synccheck; do
  timeout 120 /usr/local/cuda/bin/compute-sanitizer --tool $tool --error-exitcode 9 .devrun/expanse_cuda_tests --small > /tmp/san.log 2>&1; echo "$tool rc $?"; tail -1 /tmp/san.log; (echo "=== $tool"; cat /tmp/san.log) >> $OUT/call11-sanitizers.log
done
timeout 100 .devrun/expanse_bench_cuda --sizes 4096 --dists uniform,kuzmin --reps 5 > $OUT/call11-bench.jsonl
python3 -c "
import json
for l in open('$OUT/call11-bench.jsonl'):
  r=json.loads(l); s=r['pipeline_device_stages_ms']; print(r['distribution'], round(sum(v for k,v in s.items() if k not in ('upload','download')),2), r['deferred'])"
