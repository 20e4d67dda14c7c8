#!/usr/bin/env bash
# Session 20 call 8: call 7's timelines at 4096^2 uniform showed each kernel group preferring its
# own block count: the first phase ends at 22.9 ms with 8 blocks against 23.6 with 6, the second
# takes 8.2 ms with 6 against 9.4 with 8, and the edge stream's long walks end at 13.2 ms with 4
# against 16.8 (6) and 21.0 (8); at 2048^2 the edge stream is the stage's tail (12.4 ms at 4
# blocks, the main stream done at 8.8-9.9). Now each group apart (EXPANSE_CUDA_BLOCKS_PER_SM=F,L,E):
# predicted 8,6,4 at 4096^2 uniform ~0.6 ms under 6,6,6; at 2048^2 no better than 4,4,4 unless the
# edge tail moves; quantile inputs perhaps from an edge stream at 4 or 6. Two rounds alternated.
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $OUT/call8-groups.jsonl; }
B=.devrun/expanse_bench_cuda
for round in 1 2; do
  for v in 6,6,6 8,6,4 8,6,6 6,6,4 8,8,4 8,6,8; do
    EXPANSE_CUDA_BLOCKS_PER_SM=$v timeout 60 $B --sizes 4096 --dists uniform --reps 5 | tag b$v-$round; done
  for v in 4,4,4 8,6,4 6,6,4 8,4,4 4,6,4; do
    EXPANSE_CUDA_BLOCKS_PER_SM=$v timeout 60 $B --sizes 1024,2048 --dists uniform --reps 7 | tag b$v-$round; done
  for v in 8,8,8 8,8,4 8,6,4 8,8,6 8,6,8; do
    EXPANSE_CUDA_BLOCKS_PER_SM=$v timeout 90 $B --sizes 2048,4096 --dists gaussian,kuzmin --reps 5 | tag b$v-$round; done
done
python3 - $OUT/call8-groups.jsonl <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'],r['side'],r['variant'].rsplit('-',1)[0])].append('%.2f (stars %.2f) def %d'%(g,s.get('stars',0),r['deferred']))
for k in sorted(d): print(k, ' | '.join(d[k]))
PY
for d in kuzmin gaussian; do echo "== $d 4096 default"; EXPANSE_CUDA_STAR_TIMELINE=1 timeout 60 $B --sizes 4096 --dists $d --reps 3 2>&1 >/dev/null | grep -i timeline | tail -1; done > $OUT/call8-timeline.txt
cat $OUT/call8-timeline.txt
