#!/usr/bin/env bash
# Session 31 call 11: the final build (call 10's, 9189ee5): the conformance suite on CUDA and
# compute-sanitizer's four tools on the CUDA tests' small cases (the CUDA tests passed in call 10).
set -u
bash bench/device/run-on-device.sh env > /dev/null 2>&1; rm -f $OUT/env.txt
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT
timeout 170 .devrun/expanse_conformance --backend cuda > $OUT/call11-conformance.log 2>&1; echo "conformance rc $?"; tail -2 $OUT/call11-conformance.log
for tool in memcheck initcheck synccheck racecheck; do
  timeout 100 /usr/local/cuda/bin/compute-sanitizer --tool $tool --error-exitcode 9 .devrun/expanse_cuda_tests --small > /tmp/san.log 2>&1; echo "$tool rc $?"; tail -1 /tmp/san.log; (echo "=== $tool"; cat /tmp/san.log) >> $OUT/call11-sanitizers.log
done
