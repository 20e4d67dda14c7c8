#!/usr/bin/env bash
# Session 32 call 4: Vn (the bundle's build: V1 with the apex filters formed only outside the
# nearest-neighbour search, which compares distances alone) against V1 (baseline/, b49d802),
# 4096^2 every input, two rounds alternated; then 1024^2 and 512^2; the CUDA tests on Vn.
set -u
bash bench/device/run-on-device.sh env > /dev/null 2>&1; cp $OUT/env.txt $OUT/call4-env.txt 2>/dev/null; rm -f $OUT/env.txt
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT .devrun/baseline/COMMIT
J=$OUT/call4-compare.jsonl
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $J; }
declare -A BIN=([Vn]=.devrun/expanse_bench_cuda [V1]=.devrun/baseline/expanse_bench_cuda)
for round in 1 2; do
  for v in V1 Vn; do
    timeout 150 ${BIN[$v]} --sizes 4096 --dists uniform,gaussian,grid,kuzmin --reps 5 | tag $v
  done
done
for v in V1 Vn; do
  timeout 100 ${BIN[$v]} --sizes 512,1024 --dists uniform,gaussian,grid,kuzmin --reps 7 | tag $v
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
timeout 150 .devrun/expanse_cuda_tests > $OUT/call4-cuda-tests.log 2>&1; echo "cuda tests rc $?"; grep -E "^FAIL" $OUT/call4-cuda-tests.log | head; tail -1 $OUT/call4-cuda-tests.log
