#!/usr/bin/env bash
# Session 29 call 1: A (the bundle's build): a search's end decided by the scanned box's four
# quantile boundaries instead of the region's four look-ups, no region for a site the inbox gave
# its nearest neighbour, the own cell by one look-up an axis; against session 28's final build
# (baseline/, fc11c9e's code at 3d731e3): 4096^2 every input, two rounds alternated; 512^2 to
# 2048^2 one round; kuzmin's timeline and lists, both builds.
set -u
bash bench/device/run-on-device.sh env > /dev/null 2>&1; cp $OUT/env.txt $OUT/call1-env.txt 2>/dev/null; rm -f $OUT/env.txt
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT .devrun/baseline/COMMIT
J=$OUT/call1-compare.jsonl
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $J; }
B=.devrun/expanse_bench_cuda O=.devrun/baseline/expanse_bench_cuda
for round in 1 2; do
  timeout 150 $B --sizes 4096 --dists uniform,gaussian,grid,kuzmin --reps 5 | tag A
  timeout 150 $O --sizes 4096 --dists uniform,gaussian,grid,kuzmin --reps 5 | tag base
done
timeout 100 $B --sizes 512,1024,2048 --dists uniform,gaussian,grid,kuzmin --reps 7 | tag A
timeout 100 $O --sizes 512,1024,2048 --dists uniform,gaussian,grid,kuzmin --reps 7 | tag base
python3 - $J <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'], r['side'], r['variant'])].append('%.2f (stars %.2f unpiped %.2f, def %d, seam %.4f%%, h2h %.1f)'%(g,s.get('stars',0),r['device_stages_ms'].get('stars',0),r['deferred'],100*r.get('seam_share',0),r.get('host_to_host_ms',0)))
for k in sorted(d): print(*k, ' / '.join(d[k]))
PY
for b in A:$B base:$O; do
  echo "== kuzmin ${b%%:*}"; EXPANSE_CUDA_STAR_TIMELINE=1 timeout 60 ${b#*:} --sizes 4096 --dists kuzmin --reps 1 2>&1 >/dev/null | grep "star stage" | tail -2
done > $OUT/call1-timeline.txt
cat $OUT/call1-timeline.txt
