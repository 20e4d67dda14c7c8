#!/usr/bin/env bash
# Session 33 call 3: the best's lift kept in registers (formed when the best changes, not for
# every candidate) at 7 blocks a multiprocessor (72 registers a thread) against session 32's
# final code (baseline/, ffeff5d, 8,6,6). Two builds of dda07cd + the experiment's switches:
# N7 (lift formed per candidate, the middle block count compiled as 7 instead of 6) and K7 (lift
# kept, middle count 7); EXPANSE_CUDA_BLOCKS_PER_SM picks first,later,edge. 4096^2 uniform and
# kuzmin, two rounds alternated.
set -u
bash bench/device/run-on-device.sh env > /dev/null 2>&1; cp $OUT/env.txt $OUT/call3-env.txt 2>/dev/null; rm -f $OUT/env.txt
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/baseline/COMMIT
J=$OUT/call3-compare.jsonl
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $J; }
run() { local name=$1 bin=$2 blocks=$3; if [ -n "$blocks" ]; then EXPANSE_CUDA_BLOCKS_PER_SM=$blocks timeout 100 $bin --sizes 4096 --dists uniform,kuzmin --reps 5 | tag "$name"; else timeout 100 $bin --sizes 4096 --dists uniform,kuzmin --reps 5 | tag "$name"; fi; }
for round in 1 2; do
  run base .devrun/baseline/expanse_bench_cuda ""
  run "N7 8,7,7" .devrun/n7/expanse_bench_cuda 8,7,7
  run "N7 7,7,7" .devrun/n7/expanse_bench_cuda 7,7,7
  run "K7 8,7,7" .devrun/k7/expanse_bench_cuda 8,7,7
  run "K7 7,7,7" .devrun/k7/expanse_bench_cuda 7,7,7
  run "K7 8,8,8" .devrun/k7/expanse_bench_cuda 8,8,8
done
python3 - $J <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'], r['side'], r['variant'])].append('%.2f (stars %.2f, def %d, pred %d)'%(g,s.get('stars',0),r['deferred'],r['predicates']))
for k in sorted(d): print(*k, ' / '.join(d[k]))
PY
for v in "base .devrun/baseline/expanse_bench_cuda" "K7-7,7,7 .devrun/k7/expanse_bench_cuda" "K7-8,7,7 .devrun/k7/expanse_bench_cuda"; do
  set -- $v; b=${1#K7-}; [ "$1" = base ] && b=8,6,6
  echo "== $1 uniform"; EXPANSE_CUDA_BLOCKS_PER_SM=$b EXPANSE_CUDA_STAR_TIMELINE=1 timeout 40 $2 --sizes 4096 --dists uniform --reps 3 2>&1 >/dev/null | grep "star stage timeline" | tail -1
done | tee $OUT/call3-timelines.txt
for v in base n7 k7; do b=.devrun/$v/expanse_bench_cuda; [ $v = base ] && b=.devrun/baseline/expanse_bench_cuda; echo "== $v"; /usr/local/cuda/bin/cuobjdump -res-usage $b 2>/dev/null | grep -A1 "star_kernel\|star_list" | grep -o "Function [^ ]*\|REG:[0-9]*\|STACK:[0-9]*" | paste - - - | sed 's/_ZN7expanse6detail4cuda48_GLOBAL__N__[0-9a-f_]*star_kernels_cu_[0-9a-f]*//' | grep "Li[78]ELb0ELb1" ; done > $OUT/call3-res-usage.txt 2>&1
