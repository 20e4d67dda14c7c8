#!/usr/bin/env bash
# Session 32 call 8: the final build (call 7's, d590016): the conformance suite on CUDA and
# compute-sanitizer's four tools on the CUDA tests' small cases (the CUDA tests passed in call 7).
set -u
bash bench/device/run-on-device.sh env > /dev/null 2>&1; rm -f $OUT/env.txt
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT
timeout 150 .devrun/expanse_conformance --backend cuda > $OUT/call8-conformance.log 2>&1; echo "conformance rc $?"; tail -2 $OUT/call8-conformance.log
for tool in memcheck initcheck synccheck racecheck; do
  timeout 70 /usr/local/cuda/bin/compute-sanitizer --tool $tool --error-exitcode 9 .devrun/expanse_cuda_tests --small > /tmp/san.log 2>&1; echo "$tool rc $?"; tail -1 /tmp/san.log; (echo "=== $tool"; cat /tmp/san.log) >> $OUT/call8-sanitizers.log
done
