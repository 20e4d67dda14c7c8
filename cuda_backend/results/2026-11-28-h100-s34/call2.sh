#!/usr/bin/env bash
# Session 34 call 2: the candidate loop with the budget test back in it, predicates counted
# without the phase test, a, b and the best turned away where flagged, the filter factors as
# immediates (HEAD: the lifted incircle; R: the incircle regrouped, 640a23c) against session
# 32's code (baseline/, ffeff5d). 4096^2 two rounds alternated, timelines.
set -u
bash bench/device/run-on-device.sh env > /dev/null 2>&1; cp $OUT/env.txt $OUT/call2-env.txt 2>/dev/null; rm -f $OUT/env.txt
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT .devrun/baseline/COMMIT .devrun/varR/COMMIT
J=$OUT/call2-compare.jsonl
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $J; }
declare -A BIN=([HEAD]=.devrun/expanse_bench_cuda [base]=.devrun/baseline/expanse_bench_cuda [R]=.devrun/varR/expanse_bench_cuda)
for v in base R HEAD; do timeout 120 ${BIN[$v]} --sizes 4096 --dists uniform,gaussian,grid,kuzmin --reps 5 | tag $v; done
for v in HEAD R base; do timeout 120 ${BIN[$v]} --sizes 4096 --dists uniform,kuzmin --reps 5 | tag $v; done
python3 - $J <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'], r['side'], r['variant'])].append('%.2f (stars %.2f, def %d, pred %d, seam %.5f%%, h2h %.1f)'%(g,s.get('stars',0),r['deferred'],r['predicates'],100*r.get('seam_share',0),r.get('host_to_host_ms',0)))
for k in sorted(d): print(*k, ' / '.join(d[k]))
PY
for v in base R HEAD; do echo "== $v uniform"; EXPANSE_CUDA_STAR_TIMELINE=1 timeout 40 ${BIN[$v]} --sizes 4096 --dists uniform --reps 3 2>&1 >/dev/null | grep "star stage timeline" | tail -1; done | tee $OUT/call2-timelines.txt
