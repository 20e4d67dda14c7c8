#!/usr/bin/env bash
# Bundles what bench/device/run-on-device.sh runs into .devrun/bundle.tar.xz (git-ignored,
# carried with the device tool's `carry`): the test and benchmark programs of a CUDA build, their
# shared libraries, the Khronos validation layer (the GPU machine has no Debian packages), and
# the commit they were built from. Compressed: each program links every backend's kernels, and
# the tool carries at most 64 MiB.
#
#   bash bench/device/bundle.sh [BUILD_DIR]     (default: build-device)
#
# EXPANSE_BASELINE=DIR adds DIR's expanse_bench_cuda, and its expanse-bench if there (a build of
# the commit a change is measured against, same libraries), as baseline/: run-on-device.sh's
# `compare` step runs both builds alternately in one run.
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
build="$(realpath "${1:-$root/build-device}")"
cd "$root"
rm -rf .devrun
mkdir -p .devrun
# EXPANSE_BUNDLE picks the programs (the tracked tree and the bundle together must stay under the
# tool's 64 MiB): `all` (the default) every one; `cuda` the benchmark, the CUDA tests and the
# conformance suite; `cuda-tests` the benchmark and the CUDA tests (timing runs with a baseline);
# `bench` the benchmark alone; `conformance` the conformance suite alone.
mode=${EXPANSE_BUNDLE:-all}
programs=()
if [[ $mode != conformance ]]; then programs+=("$build/bench/expanse_bench_cuda"); fi
if [[ $mode != bench && $mode != conformance ]]; then programs+=("$build/tests/cuda/expanse_cuda_tests"); fi
if [[ $mode != bench && $mode != cuda-tests ]]; then programs+=("$build/tests/expanse_conformance"); fi
if [[ $mode == all ]]; then
  programs+=(
    "$build/tools/expanse"
    "$build/tests/vulkan/expanse_vulkan_tests"
    "$build/tests/vulkan/expanse_vulkan_interop_tests"
    "$build/bench/expanse-bench"
    "$build/bench/expanse-bench-host-stages"
    "$build/bench/expanse-bench-page-faults"
  )
fi
# Each program and the shared libraries it needs that the GPU machine lacks (everything but the C
# and C++ runtimes and the Vulkan and CUDA drivers' loaders).
mkdir -p .devrun/lib
for program in "${programs[@]}"; do
  cp -f "$program" .devrun/
  ldd "$program" | awk '/=> \//{print $3}' | while read -r lib; do
    case "$(basename "$lib")" in
      libc.so*|libm.so*|libstdc++.so*|libgcc_s.so*|ld-linux*|libpthread.so*|libdl.so*|librt.so*|libvulkan.so*|libcuda.so*) ;;
      *) cp -fL "$lib" .devrun/lib/ ;;
    esac
  done
done
layer=/usr/lib/x86_64-linux-gnu/libVkLayer_khronos_validation.so
manifest=/usr/share/vulkan/explicit_layer.d/VkLayer_khronos_validation.json
# The validation layer only where Vulkan runs (the conformance suite on Vulkan, the Vulkan tests).
if [[ ($mode == all || $mode == cuda) && -f $layer && -f $manifest ]]; then
  mkdir -p .devrun/layers
  strip -o .devrun/layers/libVkLayer_khronos_validation.so "$layer"
  # A relative library_path is read relative to the manifest.
  sed 's|"library_path": *"[^"]*"|"library_path": "./libVkLayer_khronos_validation.so"|' \
    "$manifest" >.devrun/layers/VkLayer_khronos_validation.json
fi
if [[ -n ${EXPANSE_BASELINE:-} ]]; then
  mkdir -p .devrun/baseline
  cp "$EXPANSE_BASELINE/expanse_bench_cuda" .devrun/baseline/
  # expanse-bench only where the baseline has it: both together can push the bundle past what
  # the device tool carries.
  if [[ -f $EXPANSE_BASELINE/expanse-bench ]]; then cp "$EXPANSE_BASELINE/expanse-bench" .devrun/baseline/; fi
  cp "$EXPANSE_BASELINE/COMMIT" .devrun/baseline/ 2>/dev/null || echo "unknown" >.devrun/baseline/COMMIT
fi
git describe --always --dirty --abbrev=12 >.devrun/COMMIT
tar -C .devrun -cf - --exclude=bundle.tar.xz . | xz -T2 -6 >.devrun.tar.xz
find .devrun -mindepth 1 -delete
mv .devrun.tar.xz .devrun/bundle.tar.xz
du -sh .devrun
