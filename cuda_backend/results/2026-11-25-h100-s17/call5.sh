#!/usr/bin/env bash
# Session 17 call 5: 149b3e6 as it stands (the merge's run tables, the scale folded in, the
# interior retry budget 2^13). The full sweep 32^2-4096^2, four inputs, and a second round of
# 512^2 and 4096^2; expanse-bench's scaling (Figs. IV.2, IV.3) on CUDA and Vulkan; CUDA tests;
# conformance on CUDA with one and two phases; the four compute-sanitizer tools.
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
nvidia_icd=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json; [[ -f $nvidia_icd ]] && export VK_DRIVER_FILES=$nvidia_icd
cat .devrun/COMMIT; uptime
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $OUT/call5-sweep.jsonl; }
timeout 200 .devrun/expanse_bench_cuda --sizes 32,64,128,256,512,1024,2048,4096 --dists uniform,kuzmin,gaussian,grid --reps 5 | tag head-1
timeout 120 .devrun/expanse_bench_cuda --sizes 512,4096 --dists uniform,kuzmin,gaussian,grid --reps 5 | tag head-2
python3 - $OUT/call5-sweep.jsonl <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'],r['side'])].append('%.2f (stars %.2f) h2h %.1f def %d seam %.6f'%(g,s.get('stars',0),r.get('host_to_host_ms',0),r['deferred'],r.get('seam_share',0)))
for k in sorted(d): print(k, ' | '.join(d[k]))
PY
EXPANSE_COMMIT=$(cat .devrun/COMMIT) timeout 200 .devrun/expanse-bench --experiment scaling --backends cuda,vulkan --dist uniform,gaussian \
  -n 32^2,64^2,128^2,256^2,512^2,1024^2,2048^2,4096^2 --layouts default -r 5 --max-seconds 8 --note "device run" --warmup 1 \
  -o $OUT/scaling.jsonl > /tmp/scaling.log 2>&1; echo "scaling rc $?"; tail -3 /tmp/scaling.log
timeout 200 .devrun/expanse_cuda_tests > $OUT/call5-cuda-tests.log 2>&1; echo "cuda tests rc $?"; grep -E "interior|FAIL" $OUT/call5-cuda-tests.log; tail -1 $OUT/call5-cuda-tests.log
timeout 200 .devrun/expanse_conformance --backend cuda > $OUT/call5-conformance.log 2>&1; echo "conformance rc $?"; tail -2 $OUT/call5-conformance.log
EXPANSE_CUDA_PHASES=2 timeout 200 .devrun/expanse_conformance --backend cuda >> $OUT/call5-conformance.log 2>&1; echo "conformance (two phases) rc $?"; tail -2 $OUT/call5-conformance.log
for tool in memcheck racecheck initcheck synccheck; do
  timeout 120 /usr/local/cuda/bin/compute-sanitizer --tool $tool --error-exitcode 9 .devrun/expanse_cuda_tests --small > /tmp/san.log 2>&1; echo "$tool rc $?"; tail -1 /tmp/san.log; (echo "=== $tool"; cat /tmp/san.log) >> $OUT/call5-sanitizers.log
done
