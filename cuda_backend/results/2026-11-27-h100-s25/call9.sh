#!/usr/bin/env bash
# Session 25 call 9 (cfa5db4): the tails' weighing shared with Vulkan's quantile cells. Vulkan on
# the H100, kuzmin 4096^2 (expanse-bench, host to host and its device stages), EXPANSE_VULKAN_TAILS=0
# against the default, two rounds alternated; lavapipe had its seam share 0.57% -> 0.19% and the
# time within noise (-3.6% in medians) at 10^6. Then the CUDA path, which the move should not
# change (kuzmin 4096^2 ~59.6 ms), the CUDA tests, and conformance on CUDA and on Vulkan.
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT
J=$OUT/call9-vulkan-tails.jsonl
for round in 1 2; do
  for v in 0 default; do
    if [ $v = 0 ]; then export EXPANSE_VULKAN_TAILS=0; else unset EXPANSE_VULKAN_TAILS; fi
    timeout 120 .devrun/expanse-bench --experiment tails --backends vulkan --dist kuzmin -n 4096^2 -r 3 --warmup 1 \
      --note "EXPANSE_VULKAN_TAILS=$v" -o $J > /dev/null 2>&1; echo "vulkan $v rc $?"
  done
done
unset EXPANSE_VULKAN_TAILS
python3 - $J <<'PY'
import json,sys
for l in open(sys.argv[1]):
  r=json.loads(l)
  if r.get('skipped'): print('skipped', r.get('reason')); continue
  print(r['note'], 'total %.1f'%r['time_ms']['total']['median'], {k:round(v,1) for k,v in r.get('device_stages_ms',{}).items()}, 'seam %.4f%%'%(100*r.get('seam_share',0)), 'deferred', r.get('deferred'))
PY
timeout 100 .devrun/expanse_bench_cuda --sizes 4096 --dists kuzmin,uniform --reps 5 > $OUT/call9-cuda.jsonl
python3 - $OUT/call9-cuda.jsonl <<'PY'
import json,sys
for l in open(sys.argv[1]):
  try: r=json.loads(l)
  except Exception: continue
  s=r['pipeline_device_stages_ms']; g=sum(v for k,v in s.items() if k not in ('upload','download'))
  print('cuda', r['distribution'], 'GPU-only %.2f stars %.2f deferred %d'%(g, s['stars'], r['deferred']))
PY
timeout 200 .devrun/expanse_cuda_tests > $OUT/call9-cuda-tests.log 2>&1; echo "cuda tests rc $?"; tail -1 $OUT/call9-cuda-tests.log
for b in cuda vulkan; do
  timeout 150 .devrun/expanse_conformance --backend $b > $OUT/call9-conformance-$b.log 2>&1; echo "conformance $b rc $?"; tail -2 $OUT/call9-conformance-$b.log
done
