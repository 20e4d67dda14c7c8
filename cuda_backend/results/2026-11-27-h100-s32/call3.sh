#!/usr/bin/env bash
# Session 32 call 3: Vk (the bundle's build: V1 + the incircle filter's bound factor multiplied
# into the best's lift, apex_lift_prescaled, one product off each candidate's longest chain)
# against V1 (baseline/, b49d802), 4096^2 every input, two rounds alternated; then uniform and
# gaussian with the star kernels' blocks a multiprocessor varied (EXPANSE_CUDA_BLOCKS_PER_SM),
# both builds; the CUDA tests on Vk.
set -u
bash bench/device/run-on-device.sh env > /dev/null 2>&1; cp $OUT/env.txt $OUT/call3-env.txt 2>/dev/null; rm -f $OUT/env.txt
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT .devrun/baseline/COMMIT
J=$OUT/call3-compare.jsonl
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $J; }
declare -A BIN=([Vk]=.devrun/expanse_bench_cuda [V1]=.devrun/baseline/expanse_bench_cuda)
for round in 1 2; do
  for v in V1 Vk; do
    timeout 150 ${BIN[$v]} --sizes 4096 --dists uniform,gaussian,grid,kuzmin --reps 5 | tag $v
  done
done
for blocks in 6,6,6 8,8,8 8,6,8 6,6,8; do
  for v in V1 Vk; do
    EXPANSE_CUDA_BLOCKS_PER_SM=$blocks timeout 100 ${BIN[$v]} --sizes 4096 --dists uniform,gaussian --reps 5 | tag "$v blocks $blocks"
  done
done
python3 - $J <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'], r['side'], r['variant'])].append('%.2f (stars %.2f, def %d)'%(g,s.get('stars',0),r['deferred']))
for k in sorted(d): print(*k, ' / '.join(d[k]))
PY
timeout 150 .devrun/expanse_cuda_tests > $OUT/call3-cuda-tests.log 2>&1; echo "cuda tests rc $?"; grep -E "^FAIL" $OUT/call3-cuda-tests.log | head; tail -1 $OUT/call3-cuda-tests.log
