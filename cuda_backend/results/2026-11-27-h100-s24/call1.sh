#!/usr/bin/env bash
# Session 24 call 1: does the edge's stream slow the first phase? Kuzmin's edge first pass ends
# at 36 ms of a 39 ms first phase (session 22 call 8): ~180 blocks of the ring's ~23k far-tail
# sites holding 1/6 of the slots. Timelines and list lengths at 4096^2 (uniform, gaussian,
# kuzmin), default against the edge started after the first phase (EXPANSE_CUDA_EDGE_AFTER) and
# the edge's first pass at lower budgets (EXPANSE_CUDA_EDGE_FIRST_BUDGET).
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT
B=.devrun/expanse_bench_cuda
J=$OUT/call1-edge.jsonl
run() {  # variant dist env...
  local v=$1 d=$2; shift 2
  echo "== $v $d"
  env "$@" EXPANSE_CUDA_STAR_TIMELINE=1 timeout 100 $B --sizes 4096 --dists $d --reps 3 2>/tmp/tl.txt | python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$v'; print(json.dumps(r))" >> $J
  grep -h "star stage" /tmp/tl.txt | tail -2
}
for d in kuzmin uniform gaussian; do
  run default $d X=1
  run after0 $d EXPANSE_CUDA_EDGE_AFTER=phase0
  run edge256 $d EXPANSE_CUDA_EDGE_FIRST_BUDGET=256
done
run edge1024 kuzmin EXPANSE_CUDA_EDGE_FIRST_BUDGET=1024
run edge64 kuzmin EXPANSE_CUDA_EDGE_FIRST_BUDGET=64
run depth0 kuzmin EXPANSE_CUDA_EDGE_DEPTH=0
run depth2 kuzmin EXPANSE_CUDA_EDGE_DEPTH=2
run depth0 uniform EXPANSE_CUDA_EDGE_DEPTH=0
python3 - $J <<'PY'
import json,sys
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  print(r['variant'], r['distribution'], r['side'], '%.2f (stars %.2f) def %d'%(g,s.get('stars',0),r['deferred']))
PY
