#!/usr/bin/env bash
# Builds everything and runs the whole test suite: unit tests, the conformance suite on every
# backend (GPU backends without a device are reported as skipped), CLI tests, and the quick
# benchmark so the benchmarks cannot rot.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$(nproc)"
# The quick benchmark proves the benchmark programs and the report still run; its numbers go
# to bench/out/quick/ and are quoted nowhere (docs/benchmarks.md comes from the full mode).
bash bench/run.sh --quick --build-dir build --no-build
cd build
ctest --output-on-failure -j"$(nproc)" --timeout 2400
