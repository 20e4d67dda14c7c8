#!/usr/bin/env bash
# Session 17 call 4: the main stream's retry budget (EXPANSE_CUDA_RETRY_BUDGET: the warps'
# second pass of the sites away from the grid's edge) 2^16 (the default) / 2^15 / 2^14 / 2^13,
# 2048^2 and 4096^2, gaussian, kuzmin, uniform, two rounds alternated, with the star stage's
# timeline; GPU-only, host to host, the seam's growth and share.
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $OUT/call4-retry-budget.jsonl; }
for round in 1 2; do
  for b in 65536 32768 16384 8192; do
    EXPANSE_CUDA_RETRY_BUDGET=$b EXPANSE_CUDA_STAR_TIMELINE=1 timeout 100 .devrun/expanse_bench_cuda --sizes 2048,4096 --dists gaussian,kuzmin,uniform --reps 5 2> /tmp/timeline.txt | tag b$b-$round
    (echo "=== budget $b round $round"; grep timeline /tmp/timeline.txt) >> $OUT/call4-timeline.txt
  done
done
python3 - $OUT/call4-retry-budget.jsonl <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  p=r.get('pipeline_stages_ms') or {}
  d[(r['distribution'],r['side'],r['variant'].split('-')[0])].append('%.2f (stars %.2f) h2h %.1f seam %.2f def %d share %.6f'%(g,s.get('stars',0),r.get('host_to_host_ms',0),p.get('seam: growth',0),r['deferred'],r.get('seam_share',0)))
for k in sorted(d): print(k, ' | '.join(d[k]))
PY
