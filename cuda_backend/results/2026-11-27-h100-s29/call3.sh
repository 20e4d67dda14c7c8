#!/usr/bin/env bash
# Session 29 call 3: two shapes of the same change, against session 28's final build (baseline/),
# the first phase's retry back beside the second phase in both: E2 (the bundle's build: D's
# code, 2ad1e7f, with the retry back and the lattice's walks kept out of the boundaries' test
# too) and E1 (e1/: E2 with the region computed as in A, call 1: its bounds first, one look-up
# at the end). 4096^2 every input, two rounds alternated; 2048^2 one round.
set -u
python3 -c "import tarfile; tarfile.open('.devrun/bundle.tar.xz').extractall('.devrun')"
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT .devrun/e1/COMMIT .devrun/baseline/COMMIT; nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
J=$OUT/call3-compare.jsonl
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $J; }
B=.devrun/expanse_bench_cuda E=.devrun/e1/expanse_bench_cuda O=.devrun/baseline/expanse_bench_cuda
for round in 1 2; do
  timeout 150 $B --sizes 4096 --dists uniform,gaussian,grid,kuzmin --reps 5 | tag E2
  timeout 150 $E --sizes 4096 --dists uniform,gaussian,grid,kuzmin --reps 5 | tag E1
  timeout 150 $O --sizes 4096 --dists uniform,gaussian,grid,kuzmin --reps 5 | tag base
done
for b in E2:$B E1:$E base:$O; do timeout 100 ${b#*:} --sizes 2048 --dists uniform,gaussian,grid,kuzmin --reps 7 | tag ${b%%:*}; done
python3 - $J <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'], r['side'], r['variant'])].append('%.2f (stars %.2f unpiped %.2f, def %d, seam %.4f%%)'%(g,s.get('stars',0),r['device_stages_ms'].get('stars',0),r['deferred'],100*r.get('seam_share',0)))
for k in sorted(d): print(*k, ' / '.join(d[k]))
PY
