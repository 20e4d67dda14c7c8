#!/usr/bin/env bash
# Session 15 call 11: Vulkan's stars in two classes with posts on GPUs (star.comp), against one class, and CUDA for the ratio (expanse-bench, 4096^2 and 1024^2, uniform and kuzmin, two rounds alternated); conformance on Vulkan in two classes with validation, the Vulkan suites.
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
nvidia_icd=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
[[ -f $nvidia_icd ]] && export VK_DRIVER_FILES="$nvidia_icd"
export VK_LAYER_PATH=$PWD/.devrun/layers
EXPANSE_VULKAN_VALIDATION=1 EXPANSE_VULKAN_STAR_PASSES=2 timeout 300 .devrun/expanse_conformance --backend vulkan > $OUT/call11-conformance-vulkan-two-classes.log 2>&1; echo "conformance vulkan two classes rc $?"; tail -1 $OUT/call11-conformance-vulkan-two-classes.log
EXPANSE_VULKAN_VALIDATION=1 timeout 300 .devrun/expanse_vulkan_tests all > $OUT/call11-vulkan-suites.log 2>&1; echo "vulkan suites rc $?"; tail -1 $OUT/call11-vulkan-suites.log
for round in 1 2; do
  timeout 200 .devrun/expanse-bench --backends cuda --dist uniform,kuzmin -n 1024^2,4096^2 -r 3 --warmup 1 --note "cuda, round $round" -o $OUT/call11-vulkan-classes.jsonl > /dev/null 2>>$OUT/call11.log
  EXPANSE_VULKAN_STAR_PASSES=1 timeout 200 .devrun/expanse-bench --backends vulkan --dist uniform,kuzmin -n 1024^2,4096^2 -r 3 --warmup 1 --note "vulkan one class, round $round" -o $OUT/call11-vulkan-classes.jsonl > /dev/null 2>>$OUT/call11.log
  timeout 200 .devrun/expanse-bench --backends vulkan --dist uniform,kuzmin -n 1024^2,4096^2 -r 3 --warmup 1 --note "vulkan two classes, round $round" -o $OUT/call11-vulkan-classes.jsonl > /dev/null 2>>$OUT/call11.log
done
python3 - $OUT/call11-vulkan-classes.jsonl <<'PY'
import json,sys
for l in open(sys.argv[1]):
  r=json.loads(l)
  t=r['time_ms']; st=r.get('device_stages_ms') or {}
  stars={k:round(v,1) for k,v in st.items() if 'star' in k}
  print(f"{r['note']:28} {r['distribution'][:5]:5} {r['n']:9} total {t['total']['median']:7.1f} device {t.get('device',{}).get('median',0):6.1f} stars {stars} deferred {r.get('deferred')} tris {r.get('triangles')}")
PY
