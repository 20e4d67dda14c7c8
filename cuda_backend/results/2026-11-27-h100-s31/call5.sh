#!/usr/bin/env bash
# Session 31 call 5: T (the bundle's build: call 4's, the other walks' code as before the scans
# across, token for token: kAcross) against session 30's final code (baseline/, ef097ed) and T
# with EXPANSE_CUDA_TAIL_COLUMNS=0: 4096^2 every input, two rounds alternated; every input 512^2
# to 2048^2; the star kernels' registers and stacks (cuobjdump); kuzmin's timelines; T's CUDA
# tests.
set -u
bash bench/device/run-on-device.sh env > /dev/null 2>&1; cp $OUT/env.txt $OUT/call5-env.txt 2>/dev/null; rm -f $OUT/env.txt
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT .devrun/baseline/COMMIT
J=$OUT/call5-compare.jsonl
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
  EXPANSE_CUDA_TAIL_COLUMNS=0 timeout 40 $B --sizes 4096 --dists kuzmin --reps 5 | tag T-off
done
timeout 80 $B --sizes 512,1024,2048 --dists uniform,gaussian,grid,kuzmin --reps 7 | tag T
timeout 80 $O --sizes 512,1024,2048 --dists uniform,gaussian,grid,kuzmin --reps 7 | tag base
for b in $B $O; do echo "== $b"; /usr/local/cuda/bin/cuobjdump -res-usage $b 2>/dev/null | grep -A1 "star\|walk" | grep -o "Function [^ ]*\|REG:[0-9]*\|STACK:[0-9]*" | paste - - - ; done > $OUT/call5-res-usage.txt 2>&1
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
done | tee $OUT/call5-timelines.txt
timeout 150 .devrun/expanse_cuda_tests > $OUT/call5-cuda-tests.log 2>&1; echo "cuda tests rc $?"; grep -E "^FAIL" $OUT/call5-cuda-tests.log | head; tail -1 $OUT/call5-cuda-tests.log
