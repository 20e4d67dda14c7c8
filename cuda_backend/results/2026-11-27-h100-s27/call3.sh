#!/usr/bin/env bash
# Session 27 call 3: (C, the bundle's build) the walks on quantile cells with both guides compiled for
# that kind (GridKind::guided: the compiler told that the boundaries and guides are there), against
# call 2's A (variantA/, a413349: a walk of its own for uniform cells only). 4096^2 every input,
# two rounds alternated; 2048^2 and 512^2; CUDA tests of C.
set -u
bash bench/device/run-on-device.sh env > $OUT/call3-env.txt 2>&1
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT .devrun/variantA/COMMIT
J=$OUT/call3-guided.jsonl
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $J; }
C=.devrun/expanse_bench_cuda A=.devrun/variantA/expanse_bench_cuda
for round in 1 2; do
  timeout 150 $C --sizes 4096 --dists uniform,gaussian,grid,kuzmin --reps 5 | tag C
  timeout 150 $A --sizes 4096 --dists uniform,gaussian,grid,kuzmin --reps 5 | tag A
done
for b in C:$C A:$A; do
  timeout 100 ${b#*:} --sizes 512,2048 --dists uniform,gaussian,kuzmin --reps 7 | tag ${b%%:*}
done
python3 - $J <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'], r['side'], r['variant'])].append('%.2f (stars %.2f, def %d, seam %.4f%%)'%(g,s.get('stars',0),r['deferred'],100*r.get('seam_share',0)))
for k in sorted(d): print(*k, ' / '.join(d[k]))
PY
timeout 200 .devrun/expanse_cuda_tests > $OUT/call3-cuda-tests.log 2>&1; echo "cuda tests rc $?"; tail -1 $OUT/call3-cuda-tests.log
