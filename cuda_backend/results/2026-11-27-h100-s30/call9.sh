#!/usr/bin/env bash
# Session 30 call 9: the first phase's retry (edge's stream, highest priority, beside the inbox
# kernel and the second phase) in fewer blocks (EXPANSE_CUDA_PHASE0_RETRY_BLOCKS 4, 2, 1 a
# multiprocessor, against 8), so that it takes fewer of the second phase's slots; one build (the
# bundle's), 4096^2 kuzmin and gaussian, two rounds alternated; kuzmin's timelines.
set -u
python3 -c "import tarfile; tarfile.open('.devrun/bundle.tar.xz').extractall('.devrun')"
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT; nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
J=$OUT/call9-compare.jsonl
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $J; }
B=.devrun/expanse_bench_cuda
for round in 1 2; do
  for v in 8 4 2 1; do
    EXPANSE_CUDA_PHASE0_RETRY_BLOCKS=$v timeout 150 $B --sizes 4096 --dists gaussian,kuzmin --reps 5 | tag blocks-$v
  done
done
python3 - $J <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'], r['variant'])].append('%.2f (stars %.2f, def %d)'%(g,s.get('stars',0),r['deferred']))
for k in sorted(d): print(*k, ' / '.join(d[k]))
PY
for v in 8 2; do
  echo "== kuzmin blocks $v"; EXPANSE_CUDA_PHASE0_RETRY_BLOCKS=$v EXPANSE_CUDA_STAR_TIMELINE=1 timeout 60 $B --sizes 4096 --dists kuzmin --reps 2 2>&1 >/dev/null | grep "star stage timeline" | tail -2
done | tee $OUT/call9-timelines.txt
