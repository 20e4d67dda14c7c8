#!/usr/bin/env bash
# The main job: install what is missing, build, triangulate a demo set on the default device
# (CUDA, else Vulkan — lavapipe when there is no GPU), print the summary, write pictures.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$(nproc)" --target expanse_cli
mkdir -p out
./build/tools/expanse info
./build/tools/expanse generate --dist gaussian -n 100000 --seed 1 -o out/demo.node
./build/tools/expanse triangulate out/demo.node -o out/demo --neighbors --svg --png --check
echo "expanse: wrote out/demo.ele, out/demo.neigh, out/demo.svg and out/demo.png"
