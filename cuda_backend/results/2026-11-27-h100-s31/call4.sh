#!/usr/bin/env bash
# Session 31 call 4: T (the bundle's build: call 3's, the scans across compiled into walks of
# their own (GridKind::guided_tails), the columns copied only where the x-tails are heavy)
# against session 30's final code (baseline/, ef097ed), T with EXPANSE_CUDA_TAIL_COLUMNS=0 and,
# for gaussian, =1: 4096^2 every input, two rounds alternated; kuzmin and gaussian 512^2 to
# 2048^2; the star kernels' registers and stacks (cuobjdump); kuzmin's timelines; T's CUDA tests.
set -u
bash bench/device/run-on-device.sh env > /dev/null 2>&1; cp $OUT/env.txt $OUT/call4-env.txt 2>/dev/null; rm -f $OUT/env.txt
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT .devrun/baseline/COMMIT
J=$OUT/call4-compare.jsonl
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $J; }
B=.devrun/expanse_bench_cuda O=.devrun/baseline/expanse_bench_cuda
for round in 1 2; do
  timeout 120 $B --sizes 4096 --dists uniform,gaussian,grid,kuzmin --reps 5 | tag T
  timeout 120 $O --sizes 4096 --dists uniform,gaussian,grid,kuzmin --reps 5 | tag base
  EXPANSE_CUDA_TAIL_COLUMNS=0 timeout 80 $B --sizes 4096 --dists gaussian,kuzmin --reps 5 | tag T-off
  EXPANSE_CUDA_TAIL_COLUMNS=1 timeout 40 $B --sizes 4096 --dists gaussian --reps 5 | tag T-on
done
timeout 60 $B --sizes 512,1024,2048 --dists gaussian,kuzmin --reps 7 | tag T
timeout 60 $O --sizes 512,1024,2048 --dists gaussian,kuzmin --reps 7 | tag base
for b in $B $O; do echo "== $b"; /usr/local/cuda/bin/cuobjdump -res-usage $b 2>/dev/null | grep -A1 "star\|walk" | grep -o "Function [^ ]*\|REG:[0-9]*\|STACK:[0-9]*" | paste - - - ; done > $OUT/call4-res-usage.txt 2>&1
python3 - $J <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'], r['side'], r['variant'])].append('%.2f (stars %.2f, bucket %.2f, def %d, seam %.4f%%)'%(g,s.get('stars',0),s.get('bucket',0),r['deferred'],100*r.get('seam_share',0)))
for k in sorted(d): print(*k, ' / '.join(d[k]))
PY
for v in T T-off; do
  echo "== kuzmin $v"; [ $v = T-off ] && export EXPANSE_CUDA_TAIL_COLUMNS=0
  EXPANSE_CUDA_STAR_TIMELINE=1 timeout 40 $B --sizes 4096 --dists kuzmin --reps 2 2>&1 >/dev/null | grep "star stage" | tail -2
  unset EXPANSE_CUDA_TAIL_COLUMNS
done | tee $OUT/call4-timelines.txt
timeout 150 .devrun/expanse_cuda_tests > $OUT/call4-cuda-tests.log 2>&1; echo "cuda tests rc $?"; grep -E "^FAIL" $OUT/call4-cuda-tests.log | head; tail -1 $OUT/call4-cuda-tests.log
