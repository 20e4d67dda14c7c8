#!/usr/bin/env bash
# Session 30 call 4: the edge's retry at the main stream's priority on a stream of its own
# (EXPANSE_CUDA_EDGE_RETRY=low, with 8 (default), 4 or 2 blocks a multiprocessor) against the
# default (the edge's stream, highest priority), one build (the bundle's), 4096^2 every input,
# two rounds alternated; star stage timelines.
set -u
python3 -c "import tarfile; tarfile.open('.devrun/bundle.tar.xz').extractall('.devrun')"
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT; nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
J=$OUT/call4-compare.jsonl
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $J; }
B=.devrun/expanse_bench_cuda
for round in 1 2; do
  for v in default low low:4 low:2; do
    EXPANSE_CUDA_EDGE_RETRY=$v timeout 150 $B --sizes 4096 --dists uniform,gaussian,grid,kuzmin --reps 5 | tag $v
  done
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
for dist in kuzmin uniform gaussian; do
  for v in default low low:2; do
    echo "== $dist $v"; EXPANSE_CUDA_EDGE_RETRY=$v EXPANSE_CUDA_STAR_TIMELINE=1 timeout 60 $B --sizes 4096 --dists $dist --reps 2 2>&1 >/dev/null | grep "star stage timeline" | tail -2
  done
done | tee $OUT/call4-timelines.txt
