#!/usr/bin/env bash
# Session 24 call 2: call 1 found the edge's stream costing the first phase 2.4 ms (uniform) to
# 3.3 ms (kuzmin) when they run side by side. Its kernels' blocks of 128 threads hold their
# slots until their slowest warp is done (the retry: a warp a site, 3,022 hull-hugging sites on
# uniform, 10,185 on kuzmin); blocks of one warp free each warp's slot as it ends. Expected:
# half the cost back (uniform -1 ms, kuzmin -1.5 ms). Two rounds, default against
# EXPANSE_CUDA_EDGE_THREADS=32 / 64 and with EXPANSE_CUDA_LIST_THREADS=32, 4096^2.
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT
B=.devrun/expanse_bench_cuda
J=$OUT/call2-edge-threads.jsonl
run() {  # variant dists env...
  local v=$1 d=$2; shift 2
  echo "== $v $d"
  env "$@" EXPANSE_CUDA_STAR_TIMELINE=1 timeout 150 $B --sizes 4096 --dists $d --reps 3 2>/tmp/tl.txt | python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$v'; print(json.dumps(r))" >> $J
  grep -h "star stage timeline" /tmp/tl.txt | awk 'NR%3==0'
}
for round in 1 2; do
  run default uniform,kuzmin,gaussian X=1
  run edge32 uniform,kuzmin,gaussian EXPANSE_CUDA_EDGE_THREADS=32
  run edge64 uniform,kuzmin,gaussian EXPANSE_CUDA_EDGE_THREADS=64
  run edge32list32 uniform,kuzmin,gaussian EXPANSE_CUDA_EDGE_THREADS=32 EXPANSE_CUDA_LIST_THREADS=32
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
