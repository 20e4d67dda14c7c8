#!/usr/bin/env bash
# Session 29 call 11: the final build (e15dfa3, H's code): CUDA tests, the conformance suite on
# CUDA, compute-sanitizer's four tools on the CUDA tests' small cases.
set -u
python3 -c "import tarfile; tarfile.open('.devrun/bundle.tar.xz').extractall('.devrun')"
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT; nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
timeout 150 .devrun/expanse_cuda_tests > $OUT/call11-cuda-tests.log 2>&1; echo "cuda tests rc $?"; grep -E "^FAIL" $OUT/call11-cuda-tests.log | head; tail -1 $OUT/call11-cuda-tests.log
timeout 170 .devrun/expanse_conformance --backend cuda > $OUT/call11-conformance.log 2>&1; echo "conformance rc $?"; tail -2 $OUT/call11-conformance.log
for tool in memcheck initcheck synccheck racecheck; do
  timeout 60 /usr/local/cuda/bin/compute-sanitizer --tool $tool --error-exitcode 9 .devrun/expanse_cuda_tests --small > /tmp/san.log 2>&1; echo "$tool rc $?"; tail -1 /tmp/san.log; (echo "=== $tool"; cat /tmp/san.log) >> $OUT/call11-sanitizers.log
done
