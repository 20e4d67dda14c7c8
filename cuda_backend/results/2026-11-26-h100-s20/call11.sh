#!/usr/bin/env bash
# Session 20 call 11: the knobs tuned at 8 blocks a multiprocessor, again under the new block
# counts (HEAD's build): sites per uniform cell (--sites-per-bucket 1.75 / 2 (default, 3.5 a cell)
# / 2.25 / 2.5) at 2048^2 and 4096^2 uniform; at 4096^2 the first pass's budget (512, 2048) and
# the edge stream's depth (2). Expected: within noise, as call 4 found at 8 blocks; a cell size
# that pays would show as >1% in both rounds. Two rounds alternated.
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $OUT/call11-knobs.jsonl; }
B=.devrun/expanse_bench_cuda
for round in 1 2; do
  for spb in 2 1.75 2.25 2.5; do
    timeout 60 $B --sizes 2048,4096 --dists uniform --reps 5 --sites-per-bucket $spb | tag spb$spb-$round; done
  for v in EXPANSE_CUDA_FIRST_BUDGET=512 EXPANSE_CUDA_FIRST_BUDGET=2048 EXPANSE_CUDA_EDGE_DEPTH=2; do
    env $v timeout 60 $B --sizes 4096 --dists uniform --reps 5 | tag "$v-$round"; done
done
python3 - $OUT/call11-knobs.jsonl <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'],r['side'],r['variant'].rsplit('-',1)[0])].append('%.2f (stars %.2f bucket %.2f) def %d'%(g,s.get('stars',0),s.get('bucket',0),r['deferred']))
for k in sorted(d): print(k, ' | '.join(d[k]))
PY
