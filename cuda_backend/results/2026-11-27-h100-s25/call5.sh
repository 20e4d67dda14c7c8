#!/usr/bin/env bash
# Session 25 call 5: settings tuned before the weighed tails, tried again on kuzmin (and
# gaussian) 4096^2, two rounds alternated in one binary:
#  - the weighing itself (EXPANSE_CUDA_TAILS=share,factor; default 40,3): flat on the CPU
#    (80.2-80.8 units a site for 25..100, 2..4), so expected within noise;
#  - the first pass's budget on quantile cells (2^12 above 2^23 sites, chosen because kuzmin's
#    stretched cells put sites just past 2^10 and 2^11; the weighing cut those 3.4x):
#    EXPANSE_CUDA_FIRST_BUDGET=2048 / 1024 might now win;
#  - the second phase at 6 blocks a multiprocessor (EXPANSE_CUDA_BLOCKS_PER_SM=8,6,8), which
#    lost kuzmin 0.7 ms in session 20 and gained gaussian as much;
#  - EXPANSE_CUDA_SITES_COPY=before: call 2-3's pipelined kuzmin stars ran 1.5 ms longer than
#    unpipelined, uniform's not; with the sites' copy to the host before the growth, is it gone?
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT
J=$OUT/call5-settings.jsonl
B=.devrun/expanse_bench_cuda
run() {  # variant dists env...
  local v=$1 d=$2; shift 2
  env "$@" timeout 100 $B --sizes 4096 --dists $d --reps 5 | python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$v'; print(json.dumps(r))" >> $J
}
for round in 1 2; do
  run default kuzmin,gaussian X=1
  run tails40,2 kuzmin EXPANSE_CUDA_TAILS=40,2
  run tails40,5 kuzmin EXPANSE_CUDA_TAILS=40,5
  run tails25,4 kuzmin EXPANSE_CUDA_TAILS=25,4
  run tails80,3 kuzmin EXPANSE_CUDA_TAILS=80,3
  run first2048 kuzmin,gaussian EXPANSE_CUDA_FIRST_BUDGET=2048
  run first1024 kuzmin,gaussian EXPANSE_CUDA_FIRST_BUDGET=1024
  run blocks868 kuzmin,gaussian EXPANSE_CUDA_BLOCKS_PER_SM=8,6,8
  run copybefore kuzmin EXPANSE_CUDA_SITES_COPY=before
done
python3 - $J <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  u=r.get('device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'], r['variant'])].append('%.2f (stars %.2f/%.2f unpiped, bucket %.2f, def %d)'%(g,s.get('stars',0),u.get('stars',0),s.get('bucket',0),r['deferred']))
for k in sorted(d): print(*k, ' / '.join(d[k]))
PY
