#!/usr/bin/env bash
# Session 33 call 5: the thread walk's candidates taken one an iteration of the scan loop (HEAD)
# against session 32's final code (baseline/, ffeff5d) at every size, 4096^2 in two rounds
# alternated; timelines; the CUDA tests; ncu's source counters on the first phase's kernel again.
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
declare -A BIN=([HEAD]=.devrun/expanse_bench_cuda [base]=.devrun/baseline/expanse_bench_cuda)
for round in 1 2; do
  for v in base HEAD; do timeout 150 ${BIN[$v]} --sizes 4096 --dists uniform,gaussian,grid,kuzmin --reps 5 | tag $v; done
done
for v in base HEAD; do timeout 150 ${BIN[$v]} --sizes 512,1024,2048 --dists uniform,gaussian,grid,kuzmin --reps 7 | tag $v; done
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
for v in base HEAD; do
  for dist in uniform kuzmin; do
    echo "== $v $dist"; EXPANSE_CUDA_STAR_TIMELINE=1 timeout 40 ${BIN[$v]} --sizes 4096 --dists $dist --reps 3 2>&1 >/dev/null | grep "star stage timeline" | tail -1
  done
done | tee $OUT/call5-timelines.txt
timeout 150 .devrun/expanse_cuda_tests > $OUT/call5-cuda-tests.log 2>&1; echo "cuda tests rc $?"; grep -E "^FAIL|FAILED" $OUT/call5-cuda-tests.log | head -5; tail -1 $OUT/call5-cuda-tests.log
N=/usr/local/cuda/bin/ncu
timeout 200 $N -k regex:"^star_kernel$" --launch-skip 1 --launch-count 1 --section SourceCounters --section WarpStateStats \
  --page source --print-source sass --csv ${BIN[HEAD]} --sizes 4096 --dists uniform --reps 1 --no-pipeline > $OUT/call5-ncu-sass.csv 2> $OUT/call5-ncu-stderr.txt
echo "ncu rc $?"; xz -T4 $OUT/call5-ncu-sass.csv 2>/dev/null
