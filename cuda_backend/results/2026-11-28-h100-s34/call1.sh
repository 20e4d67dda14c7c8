#!/usr/bin/env bash
# Session 34 call 1: the candidate loop's bookkeeping once a segment and the filters' factors as
# immediates (varA, 644007a), and with the incircle regrouped around the candidate's orientation
# (HEAD), against session 32's code (baseline/, ffeff5d); 4096^2 two rounds alternated, 512^2
# and 2048^2; register use of the star kernels; a timeline of each.
set -u
bash bench/device/run-on-device.sh env > /dev/null 2>&1; cp $OUT/env.txt $OUT/call1-env.txt 2>/dev/null; rm -f $OUT/env.txt
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT .devrun/baseline/COMMIT .devrun/varA/COMMIT
J=$OUT/call1-compare.jsonl
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $J; }
declare -A BIN=([HEAD]=.devrun/expanse_bench_cuda [base]=.devrun/baseline/expanse_bench_cuda [A]=.devrun/varA/expanse_bench_cuda)
for v in base A HEAD; do timeout 120 ${BIN[$v]} --sizes 4096 --dists uniform,gaussian,grid,kuzmin --reps 5 | tag $v; done
for v in HEAD A base; do timeout 120 ${BIN[$v]} --sizes 4096 --dists uniform,kuzmin --reps 5 | tag $v; done
for v in base A HEAD; do timeout 100 ${BIN[$v]} --sizes 512,2048 --dists uniform,gaussian,grid,kuzmin --reps 7 | tag $v; done
python3 - $J <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'], r['side'], r['variant'])].append('%.2f (stars %.2f, def %d, pred %d, seam %.5f%%, h2h %.1f)'%(g,s.get('stars',0),r['deferred'],r['predicates'],100*r.get('seam_share',0),r.get('host_to_host_ms',0)))
for k in sorted(d): print(*k, ' / '.join(d[k]))
PY
for v in base A HEAD; do echo "== $v"; /usr/local/cuda/bin/cuobjdump -res-usage ${BIN[$v]} 2>/dev/null | grep -A1 "star_kernel\|star_list" | grep -o "Function [^ ]*\|REG:[0-9]*\|STACK:[0-9]*" | paste - - - | sed 's/_ZN7expanse6detail4cuda48_GLOBAL__N__[0-9a-f_]*star_kernels_cu_[0-9a-f]*//' | grep "Li8ELb0ELb1" ; done > $OUT/call1-res-usage.txt 2>&1
for v in base A HEAD; do echo "== $v uniform"; EXPANSE_CUDA_STAR_TIMELINE=1 timeout 40 ${BIN[$v]} --sizes 4096 --dists uniform --reps 3 2>&1 >/dev/null | grep "star stage timeline" | tail -1; done | tee $OUT/call1-timelines.txt
