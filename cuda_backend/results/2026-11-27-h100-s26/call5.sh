#!/usr/bin/env bash
# Session 26 call 5: the edge stream's settings (7050dbb, whose default walks are 7134e5c's): its
# first pass's budget (EXPANSE_CUDA_EDGE_FIRST_BUDGET: 8 sends nearly every edge site straight to
# the warps, 128, 512, the default = the first pass's) and its depth (EXPANSE_CUDA_EDGE_DEPTH 2),
# 4096^2 uniform, gaussian and kuzmin, two rounds alternated; timelines.
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT
J=$OUT/call5-edge.jsonl
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $J; }
B=.devrun/expanse_bench_cuda
D="--sizes 4096 --dists uniform,gaussian,kuzmin --reps 5"
for round in 1 2; do
  timeout 120 $B $D | tag default
  for e in 8 128 512; do EXPANSE_CUDA_EDGE_FIRST_BUDGET=$e timeout 120 $B $D | tag edge_first$e; done
  EXPANSE_CUDA_EDGE_DEPTH=2 timeout 120 $B $D | tag depth2
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
for dist in uniform kuzmin gaussian; do
  for e in 8 128; do
    echo "== timeline $dist edge first budget $e"
    EXPANSE_CUDA_EDGE_FIRST_BUDGET=$e EXPANSE_CUDA_STAR_TIMELINE=1 timeout 60 $B --sizes 4096 --dists $dist --reps 2 2>&1 >/dev/null | grep "star stage" | tail -2
  done
done > $OUT/call5-timeline.txt 2>&1
cat $OUT/call5-timeline.txt
