#!/usr/bin/env bash
# Session 15 call 10: the final code (ce5bdbf): every device suite (CUDA tests, conformance on CUDA and on Vulkan with validation, the Vulkan suites, interop), and conformance on CUDA with two phases at every size.
set -u
bash bench/device/run-on-device.sh env tests
cp $OUT/tests.log $OUT/call10-tests.log 2>/dev/null; rm -f $OUT/tests.log
export LD_LIBRARY_PATH=$PWD/.devrun/lib
EXPANSE_CUDA_PHASES=2 timeout 300 .devrun/expanse_conformance --backend cuda > $OUT/call10-conformance-two-phases.log 2>&1; echo "conformance (two phases) rc $?"; tail -1 $OUT/call10-conformance-two-phases.log
grep -E "^===== .*exit" $OUT/call10-tests.log
