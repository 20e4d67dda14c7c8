#!/usr/bin/env bash
# Session 31 call 6: call 5's build (aa54492): CUDA tests, the conformance suite on CUDA,
# compute-sanitizer memcheck, initcheck and synccheck on the CUDA tests' small cases (their
# kuzmin cases copy tail columns and scan across; one forces the copy on a gaussian).
set -u
bash bench/device/run-on-device.sh env > /dev/null 2>&1; cp $OUT/env.txt $OUT/call6-env.txt 2>/dev/null; rm -f $OUT/env.txt
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT
timeout 150 .devrun/expanse_cuda_tests > $OUT/call6-cuda-tests.log 2>&1; echo "cuda tests rc $?"; grep -E "^FAIL" $OUT/call6-cuda-tests.log | head; tail -1 $OUT/call6-cuda-tests.log
grep -E "tail columns" $OUT/call6-cuda-tests.log
timeout 170 .devrun/expanse_conformance --backend cuda > $OUT/call6-conformance.log 2>&1; echo "conformance rc $?"; tail -2 $OUT/call6-conformance.log
for tool in memcheck initcheck synccheck; do
  timeout 75 /usr/local/cuda/bin/compute-sanitizer --tool $tool --error-exitcode 9 .devrun/expanse_cuda_tests --small > /tmp/san.log 2>&1; echo "$tool rc $?"; tail -1 /tmp/san.log; (echo "=== $tool"; cat /tmp/san.log) >> $OUT/call6-sanitizers.log
done
