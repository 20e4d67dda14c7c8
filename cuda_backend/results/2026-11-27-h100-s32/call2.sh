#!/usr/bin/env bash
# Session 32 call 2: the candidate loop again. V1 (b49d802, call 1's V1), A (V1 + the incircle
# from cross products, apex_incircle_signs_crossed) and B (A + the predicate count's phase test
# the same for every candidate), 4096^2 every input, two rounds alternated; registers and stacks
# of the star kernels; uniform's and kuzmin's timelines.
# No tests: three builds fill the bundle.
set -u
bash bench/device/run-on-device.sh env > /dev/null 2>&1; cp $OUT/env.txt $OUT/call2-env.txt 2>/dev/null; rm -f $OUT/env.txt
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT .devrun/baseline/COMMIT .devrun/va/COMMIT
J=$OUT/call2-compare.jsonl
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $J; }
declare -A BIN=([B]=.devrun/expanse_bench_cuda [V1]=.devrun/baseline/expanse_bench_cuda [A]=.devrun/va/expanse_bench_cuda)
for round in 1 2; do
  for v in V1 A B; do
    timeout 150 ${BIN[$v]} --sizes 4096 --dists uniform,gaussian,grid,kuzmin --reps 5 | tag $v
  done
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
for v in V1 A B; do echo "== $v"; /usr/local/cuda/bin/cuobjdump -res-usage ${BIN[$v]} 2>/dev/null | grep -A1 "star_kernel\|star_list\|star_retry" | grep -o "Function [^ ]*\|REG:[0-9]*\|STACK:[0-9]*" | paste - - - | sed 's/_ZN7expanse6detail4cuda48_GLOBAL__N__[0-9a-f_]*star_kernels_cu_[0-9a-f]*//' ; done > $OUT/call2-res-usage.txt 2>&1
for v in V1 A B; do
  for dist in uniform kuzmin; do
    echo "== $v $dist"; EXPANSE_CUDA_STAR_TIMELINE=1 timeout 40 ${BIN[$v]} --sizes 4096 --dists $dist --reps 3 2>&1 >/dev/null | grep "star stage timeline" | tail -1
  done
done | tee $OUT/call2-timelines.txt
# (no tests in this bundle: three benchmark builds fill the 64 MiB)
