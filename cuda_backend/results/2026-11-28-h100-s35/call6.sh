#!/usr/bin/env bash
# Session 35 call 6: the conformance suite on the CUDA backend with the final build (cfe93c4's
# code: first_equal_kernel's SASS as call 5's).
set -u
export LD_LIBRARY_PATH=$PWD/.devrun/lib
bash bench/device/run-on-device.sh env > /dev/null 2>&1; grep -m1 "Product Name" $OUT/env.txt; rm -f $OUT/env.txt
cat .devrun/COMMIT
timeout 200 .devrun/expanse_conformance --backend cuda > $OUT/call6-conformance.log 2>&1; echo "conformance rc $?"; tail -3 $OUT/call6-conformance.log
