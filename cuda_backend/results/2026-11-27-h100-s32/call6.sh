#!/usr/bin/env bash
# Session 32 call 6: HEAD (b49d802, call 5's bundle) on uniform inputs with the uniform cells'
# size varied through --sites-per-bucket X (equal cells hold 1.75 X sites; default X = 2):
# 4096^2 two rounds alternated, then 512^2 to 2048^2.
set -u
bash bench/device/run-on-device.sh env > /dev/null 2>&1; rm -f $OUT/env.txt
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT
J=$OUT/call6-cells.jsonl
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $J; }
B=.devrun/expanse_bench_cuda
for round in 1 2; do
  for x in 1.5 1.625 1.75 2; do timeout 60 $B --sizes 4096 --dists uniform --reps 5 --sites-per-bucket $x | tag "X $x"; done
done
for x in 1.5 1.75 2; do timeout 90 $B --sizes 512,1024,2048 --dists uniform --reps 7 --sites-per-bucket $x | tag "X $x"; done
python3 - $J <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'], r['side'], r['variant'])].append('%.2f (stars %.2f, bucket %.2f, emit %.2f, def %d)'%(g,s.get('stars',0),s.get('bucket',0),s.get('emit',0),r['deferred']))
for k in sorted(d): print(*k, ' / '.join(d[k]))
PY
