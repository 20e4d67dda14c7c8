#!/usr/bin/env bash
# Session 31 call 7: call 5's build (aa54492): compute-sanitizer racecheck on the CUDA tests'
# small cases.
set -u
bash bench/device/run-on-device.sh env > /dev/null 2>&1; rm -f $OUT/env.txt
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT
timeout 500 /usr/local/cuda/bin/compute-sanitizer --tool racecheck --error-exitcode 9 .devrun/expanse_cuda_tests --small > $OUT/call7-racecheck.log 2>&1; echo "racecheck rc $?"; tail -2 $OUT/call7-racecheck.log
