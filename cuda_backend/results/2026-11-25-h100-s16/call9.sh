#!/usr/bin/env bash
# Session 16 call 9: sites per cell (grid density) 2 / 2.5 / 3 on 88f976c's code, re-measured
# since sessions 8-9 (star kernels then 2-4x slower): GPU-only at 2048^2 and 4096^2, four
# inputs, alternated, two rounds.
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $OUT/call9-density.jsonl; }
for round in 1 2; do
  for d in 2 2.5 3; do
    timeout 150 .devrun/expanse_bench_cuda --sizes 2048,4096 --dists uniform,kuzmin,gaussian,grid --reps 5 --sites-per-bucket $d | tag spb$d-$round
  done
done
python3 - $OUT/call9-density.jsonl <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'],r['side'],r['variant'].split('-')[0])].append('%.2f (%.2f) tri %d def %d'%(g,s.get('stars',0),r['triangles'],r['deferred']))
for k in sorted(d): print(k, ' | '.join(d[k]))
PY
