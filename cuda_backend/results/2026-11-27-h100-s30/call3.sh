#!/usr/bin/env bash
# Session 30 call 3: the edge's stream at the main stream's priority (EXPANSE_CUDA_EDGE_PRIORITY=least)
# against the highest (the default), one build (the bundle's: session 29's code with the switch),
# 4096^2 kuzmin, gaussian and uniform, two rounds alternated; their star stage timelines.
set -u
python3 -c "import tarfile; tarfile.open('.devrun/bundle.tar.xz').extractall('.devrun')"
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT; nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
J=$OUT/call3-compare.jsonl
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $J; }
B=.devrun/expanse_bench_cuda
for round in 1 2; do
  timeout 150 $B --sizes 4096 --dists uniform,gaussian,kuzmin --reps 5 | tag default
  EXPANSE_CUDA_EDGE_PRIORITY=least timeout 150 $B --sizes 4096 --dists uniform,gaussian,kuzmin --reps 5 | tag least
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
for dist in kuzmin gaussian uniform; do
  for v in default least; do
    echo "== $dist $v"; EXPANSE_CUDA_EDGE_PRIORITY=$v EXPANSE_CUDA_STAR_TIMELINE=1 timeout 60 $B --sizes 4096 --dists $dist --reps 2 2>&1 >/dev/null | grep "star stage timeline" | tail -2
  done
done | tee $OUT/call3-timelines.txt
