#!/usr/bin/env bash
# Session 20 call 2: call 1 measured the screen at -0.5 ms (4096^2 uniform) but +16 ms on kuzmin,
# whose centre lies below float resolution, and its screen-off run 5 ms slower than session 19's
# final code. Now: the screen only for searches with sites 2^-15 apart or more (kuzmin back to
# its screen-off time predicted), against bb36602 (.devrun/baseline/) in the same call, to tell
# whether the restructured walk (set_best reloading the best's point) costs without the screen.
# Two rounds alternated: baseline, screen off, screen on.
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT .devrun/baseline/COMMIT
for b in .devrun/expanse_bench_cuda .devrun/baseline/expanse_bench_cuda; do echo "== $b"; cuobjdump -res-usage $b 2>&1 | grep -A1 "star_kernel\|star_retry_kernel\|star_list_kernel" | grep -o "REG:[0-9]* STACK:[0-9]* SHARED:[0-9]* LOCAL:[0-9]*" | sort | uniq -c; done > $OUT/call2-res-usage.txt
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $OUT/call2-screen.jsonl; }
A="--sizes 4096 --dists uniform,gaussian,kuzmin --reps 5"
S="--sizes 512 --dists uniform --reps 9"
for round in 1 2; do
  timeout 150 .devrun/baseline/expanse_bench_cuda $A | tag base-$round
  EXPANSE_CUDA_SCREEN=off timeout 150 .devrun/expanse_bench_cuda $A | tag off-$round
  timeout 150 .devrun/expanse_bench_cuda $A | tag screen-$round
  timeout 60 .devrun/baseline/expanse_bench_cuda $S | tag base-$round
  EXPANSE_CUDA_SCREEN=off timeout 60 .devrun/expanse_bench_cuda $S | tag off-$round
  timeout 60 .devrun/expanse_bench_cuda $S | tag screen-$round
done
python3 - $OUT/call2-screen.jsonl <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'],r['side'],r['variant'].rsplit('-',1)[0])].append('%.2f (stars %.2f) pred %.2f def %d tri %d'%(g,s.get('stars',0),r['predicates']/r['n'],r['deferred'],r['triangles']))
for k in sorted(d): print(k, ' | '.join(d[k]))
PY
cat $OUT/call2-res-usage.txt
