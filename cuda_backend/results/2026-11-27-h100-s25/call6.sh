#!/usr/bin/env bash
# Session 25 call 6 (892ebdd, as call 5): call 5 had kuzmin 4096^2 GPU-only 61.2 ms at the default
# weighing (40,3), 59.9-60.0 at 40,5, 62.4-62.5 at 40,2 (the GPU prefers heavier weights than the
# CPU count, which was flat), and 60.4 with the first pass's budget at 2^11 instead of 2^12
# (gaussian 44.9 -> 44.3). Here both together and heavier weights, two rounds at 4096^2, then
# 512^2..2048^2 once. Expected: 40,5 with 2^11 near 59.2 ms if the two add.
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT
J=$OUT/call6-weights.jsonl
B=.devrun/expanse_bench_cuda
run() {  # variant sizes dists env...
  local v=$1 z=$2 d=$3; shift 3
  env "$@" timeout 100 $B --sizes $z --dists $d --reps 5 | python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$v'; print(json.dumps(r))" >> $J
}
for round in 1 2; do
  run default 4096 kuzmin X=1
  run w40,5 4096 kuzmin EXPANSE_CUDA_TAILS=40,5
  run w40,5+f2048 4096 kuzmin,gaussian EXPANSE_CUDA_TAILS=40,5 EXPANSE_CUDA_FIRST_BUDGET=2048
  run w40,6+f2048 4096 kuzmin EXPANSE_CUDA_TAILS=40,6 EXPANSE_CUDA_FIRST_BUDGET=2048
  run w40,8+f2048 4096 kuzmin EXPANSE_CUDA_TAILS=40,8 EXPANSE_CUDA_FIRST_BUDGET=2048
  run w30,6+f2048 4096 kuzmin EXPANSE_CUDA_TAILS=30,6 EXPANSE_CUDA_FIRST_BUDGET=2048
  run w60,6+f2048 4096 kuzmin EXPANSE_CUDA_TAILS=60,6 EXPANSE_CUDA_FIRST_BUDGET=2048
done
run default 512,1024,2048 kuzmin X=1
run w40,5 512,1024,2048 kuzmin EXPANSE_CUDA_TAILS=40,5
run w40,6 512,1024,2048 kuzmin EXPANSE_CUDA_TAILS=40,6
run w40,8 512,1024,2048 kuzmin EXPANSE_CUDA_TAILS=40,8
python3 - $J <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  u=r.get('device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'], r['side'], r['variant'])].append('%.2f (stars %.2f/%.2f unpiped, def %d)'%(g,s.get('stars',0),u.get('stars',0),r['deferred']))
for k in sorted(d): print(*k, ' / '.join(d[k]))
PY
