#!/usr/bin/env bash
# Session 33 call 1: s32-counting-bucket merged (HEAD) against session 32's final code
# (baseline/, ffeff5d): the uniform cells bucketed by the radix sort (HEAD) or by the counting
# sort (HEAD counting, EXPANSE_CUDA_BUCKET_SORT=counting), 4096^2 in two rounds alternated; the
# uniform cells' size (--sites-per-bucket X: 1.3125 X sites a cell) on HEAD; the CUDA tests.
set -u
bash bench/device/run-on-device.sh env > /dev/null 2>&1; cp $OUT/env.txt $OUT/call1-env.txt 2>/dev/null; rm -f $OUT/env.txt
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT .devrun/baseline/COMMIT
J=$OUT/call1-compare.jsonl
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $J; }
declare -A BIN=([HEAD]=.devrun/expanse_bench_cuda [base]=.devrun/baseline/expanse_bench_cuda)
B=${BIN[HEAD]}
for round in 1 2; do
  timeout 100 ${BIN[base]} --sizes 4096 --dists uniform,grid --reps 5 | tag base
  timeout 100 $B --sizes 4096 --dists uniform,grid --reps 5 | tag HEAD
  EXPANSE_CUDA_BUCKET_SORT=counting timeout 100 $B --sizes 4096 --dists uniform,grid --reps 5 | tag "HEAD counting"
done
for v in base HEAD; do timeout 60 ${BIN[$v]} --sizes 512,2048 --dists uniform --reps 7 | tag $v; done
EXPANSE_CUDA_BUCKET_SORT=counting timeout 60 $B --sizes 512,2048 --dists uniform --reps 7 | tag "HEAD counting"
for x in 1.714 1.829; do timeout 60 $B --sizes 4096 --dists uniform --reps 5 --sites-per-bucket $x | tag "HEAD X $x"; done
for x in 1.714 1.829; do EXPANSE_CUDA_BUCKET_SORT=counting timeout 60 $B --sizes 4096 --dists uniform --reps 5 --sites-per-bucket $x | tag "HEAD counting X $x"; done
python3 - $J <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'], r['side'], r['variant'])].append('%.2f (stars %.2f, bucket %.3f, def %d, h2h %.1f)'%(g,s.get('stars',0),s.get('bucket',0),r['deferred'],r.get('host_to_host_ms',0)))
for k in sorted(d): print(*k, ' / '.join(d[k]))
PY
timeout 200 .devrun/expanse_cuda_tests > $OUT/call1-cuda-tests.log 2>&1; echo "cuda tests rc $?"; grep -E "FAIL|bucket_sort" $OUT/call1-cuda-tests.log | head; tail -2 $OUT/call1-cuda-tests.log
