#!/usr/bin/env bash
# Session 17 call 6: the first pass's budget on quantile cells (EXPANSE_CUDA_FIRST_BUDGET 2^11,
# the default above 2^20 sites, against 3 * 2^10 and 2^12) now that the interior retry stops at
# 2^13; kuzmin and gaussian, 2048^2 and 4096^2, two rounds alternated, with the timeline.
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $OUT/call6-first-budget.jsonl; }
for round in 1 2; do
  for b in 2048 3072 4096; do
    EXPANSE_CUDA_FIRST_BUDGET=$b EXPANSE_CUDA_STAR_TIMELINE=1 timeout 100 .devrun/expanse_bench_cuda --sizes 2048,4096 --dists kuzmin,gaussian --reps 5 2> /tmp/timeline.txt | tag f$b-$round
    (echo "=== first budget $b round $round"; grep timeline /tmp/timeline.txt) >> $OUT/call6-timeline.txt
  done
done
python3 - $OUT/call6-first-budget.jsonl <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'],r['side'],r['variant'].split('-')[0])].append('%.2f (stars %.2f) def %d'%(g,s.get('stars',0),r['deferred']))
for k in sorted(d): print(k, ' | '.join(d[k]))
PY
