#!/usr/bin/env bash
# Session 15 call 8: Vulkan against CUDA on the H100 after CUDA's two phases (expanse-bench, 4096^2 uniform and kuzmin, two rounds alternated), and the CUDA tests once more on the final build.
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
nvidia_icd=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
[[ -f $nvidia_icd ]] && export VK_DRIVER_FILES="$nvidia_icd"
for round in 1 2; do
  for b in cuda vulkan; do
    timeout 200 .devrun/expanse-bench --backends $b --dist uniform,kuzmin -n 4096^2 -r 3 --warmup 1 --note "session 15 call 8, round $round" -o $OUT/call8-vulkan-cuda.jsonl > /dev/null 2>>$OUT/call8.log
  done
done
python3 - $OUT/call8-vulkan-cuda.jsonl <<'PY'
import json,sys
for l in open(sys.argv[1]):
  r=json.loads(l)
  t=r['time_ms']; st=r.get('stages_ms') or {}
  stars={k:round(v,1) for k,v in st.items() if 'star' in k.lower()}
  print(r['note'][-7:], r['backend'], r['distribution'], r['n'], 'total %.1f wall %.1f device %s' % (t['total']['median'], t['wall']['median'], round(t.get('device',{}).get('median',0),1)), stars)
PY
timeout 200 .devrun/expanse_cuda_tests > $OUT/call8-tests.log 2>&1; echo "cuda tests rc $?"; grep -E "FAIL|PASSED" $OUT/call8-tests.log | head -3
