#!/usr/bin/env bash
# Session 29 call 8: G (the bundle's build, ab9cb05): the star stage's switches for quantile cells
# swept again on kuzmin and gaussian 4096^2 (set long ago, before most of the walks' changes):
# blocks a multiprocessor for the edge's stream and the second phase, the first pass's budget,
# the edge's first budget and depth; two rounds alternated.
set -u
python3 -c "import tarfile; tarfile.open('.devrun/bundle.tar.xz').extractall('.devrun')"
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT; nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
J=$OUT/call8-sweep.jsonl
B=.devrun/expanse_bench_cuda
run() {  # NAME ENV...
  local name=$1; shift
  env "$@" timeout 60 $B --sizes 4096 --dists kuzmin,gaussian --reps 5 | python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$name'; print(json.dumps(r))" >> $J
}
for round in 1 2; do
  run default X=1
  run blocks-8,8,6 EXPANSE_CUDA_BLOCKS_PER_SM=8,8,6
  run blocks-8,6,8 EXPANSE_CUDA_BLOCKS_PER_SM=8,6,8
  run blocks-8,8,4 EXPANSE_CUDA_BLOCKS_PER_SM=8,8,4
  run first-1536 EXPANSE_CUDA_FIRST_BUDGET=1536
  run first-3072 EXPANSE_CUDA_FIRST_BUDGET=3072
  run edge-first-512 EXPANSE_CUDA_EDGE_FIRST_BUDGET=512
  run edge-depth-2 EXPANSE_CUDA_EDGE_DEPTH=2
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
