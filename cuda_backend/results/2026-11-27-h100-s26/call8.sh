#!/usr/bin/env bash
# Session 26 call 8: call 7's build: the four sanitizers on the CUDA tests' small cases, and the
# conformance suite on CUDA.
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT
for tool in memcheck racecheck initcheck synccheck; do
  timeout 150 /usr/local/cuda/bin/compute-sanitizer --tool $tool --error-exitcode 9 .devrun/expanse_cuda_tests --small > /tmp/san.log 2>&1; echo "$tool rc $?"; tail -1 /tmp/san.log; (echo "=== $tool"; cat /tmp/san.log) >> $OUT/call8-sanitizers.log
done
timeout 150 .devrun/expanse_conformance --backend cuda > $OUT/call8-conformance.log 2>&1; echo "conformance rc $?"; tail -2 $OUT/call8-conformance.log
