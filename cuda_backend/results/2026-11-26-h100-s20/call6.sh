#!/usr/bin/env bash
# Session 20 call 6: call 5 found fewer blocks a multiprocessor (more registers a thread) faster on
# uniform cells up to 2048^2 (4 blocks: 1024^2 4.59 against 4.97 ms at 6, 2048^2 15.6 against
# 17.0) but not at 4096^2 (4: 42.7, 5: 40.3, 6: 38.7), and kuzmin 4096^2 slower below 8. To place
# the rule: 4, 5, 6 and 8 blocks on uniform 512^2 and 2896^2 (~2^23 sites), gaussian and kuzmin at
# 512^2, 1024^2 and 2048^2 (quantile cells). Same bundle as call 5; two rounds alternated.
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $OUT/call6-blocks.jsonl; }
U="--sizes 512,2896 --dists uniform --reps 7"
Q="--sizes 512,1024,2048 --dists gaussian,kuzmin --reps 7"
for round in 1 2; do
  for b in 8 6 5 4; do
    EXPANSE_CUDA_BLOCKS_PER_SM=$b timeout 100 .devrun/expanse_bench_cuda $U | tag blocks$b-$round
    EXPANSE_CUDA_BLOCKS_PER_SM=$b timeout 100 .devrun/expanse_bench_cuda $Q | tag blocks$b-$round
  done
done
python3 - $OUT/call6-blocks.jsonl <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'],r['side'],r['variant'].rsplit('-',1)[0])].append('%.2f (stars %.2f) def %d'%(g,s.get('stars',0),r['deferred']))
for k in sorted(d): print(k, ' | '.join(d[k]))
PY
