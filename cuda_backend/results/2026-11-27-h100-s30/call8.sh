#!/usr/bin/env bash
# Session 30 call 8: with the edge's retry now at the main stream's priority, the edge's switches
# swept again on F (the bundle's build): its first pass's budget (EXPANSE_CUDA_EDGE_FIRST_BUDGET
# 1024, 512), two rings of cells (EXPANSE_CUDA_EDGE_DEPTH=2), the retry's blocks (1 and 3 a
# multiprocessor); 4096^2 kuzmin, gaussian and uniform, two rounds alternated.
set -u
python3 -c "import tarfile; tarfile.open('.devrun/bundle.tar.xz').extractall('.devrun')"
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT; nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
J=$OUT/call8-sweep.jsonl
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $J; }
B=.devrun/expanse_bench_cuda
for round in 1 2; do
  for v in default EXPANSE_CUDA_EDGE_FIRST_BUDGET=1024 EXPANSE_CUDA_EDGE_FIRST_BUDGET=512 EXPANSE_CUDA_EDGE_DEPTH=2 EXPANSE_CUDA_EDGE_RETRY=low:1 EXPANSE_CUDA_EDGE_RETRY=low:3; do
    env $([ $v = default ] || echo $v) timeout 150 $B --sizes 4096 --dists uniform,gaussian,kuzmin --reps 5 | tag $v
  done
done
python3 - $J <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'], r['variant'])].append('%.2f (def %d)'%(g,r['deferred']))
for k in sorted(d): print(*k, ' / '.join(d[k]))
PY
