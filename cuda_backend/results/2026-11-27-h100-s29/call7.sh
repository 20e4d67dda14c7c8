#!/usr/bin/env bash
# Session 29 call 7: G (the bundle's build, ab9cb05): the lattice alone and after other inputs
# in one process (below), then compute-sanitizer's four tools on the CUDA tests' small cases.
set -u
python3 -c "import tarfile; tarfile.open('.devrun/bundle.tar.xz').extractall('.devrun')"
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT; nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
# The lattice alone and after other inputs in one process: G, 3d731e3 (baseline/) and call
# 3's E1 (e1/: A's region shape in the lattice's walks too).
J=$OUT/call7-grid.jsonl
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; r['run']='$2'; print(json.dumps(r))" >> $J; }
B=.devrun/expanse_bench_cuda O=.devrun/baseline/expanse_bench_cuda E=.devrun/e1/expanse_bench_cuda
for round in 1 2; do
  for b in G:$B base:$O E1:$E; do timeout 60 ${b#*:} --sizes 4096 --dists grid --reps 5 | tag ${b%%:*} alone; done
done
for b in G:$B base:$O E1:$E; do timeout 100 ${b#*:} --sizes 4096 --dists uniform,gaussian,grid --reps 5 | tag ${b%%:*} after; done
python3 - $J <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'], r['run'], r['variant'])].append('%.2f (stars %.2f unpiped %.2f)'%(g,s.get('stars',0),r['device_stages_ms'].get('stars',0)))
for k in sorted(d): print(*k, ' / '.join(d[k]))
PY
for tool in memcheck initcheck synccheck racecheck; do
  timeout 90 /usr/local/cuda/bin/compute-sanitizer --tool $tool --error-exitcode 9 .devrun/expanse_cuda_tests --small > /tmp/san.log 2>&1; echo "$tool rc $?"; tail -1 /tmp/san.log; (echo "=== $tool"; cat /tmp/san.log) >> $OUT/call7-sanitizers.log
done
