#!/usr/bin/env bash
# Session 33 call 4: the later phase's recording kernel (inbox_star_kernel) walking each inbox
# once and writing the row as it walks (HEAD) instead of twice (EXPANSE_CUDA_INBOX_WALKS=2, as
# before), against session 32's final code (baseline/, ffeff5d); 4096^2 uniform, kuzmin,
# gaussian, two rounds alternated; timelines; then ncu's source counters (SASS, stall samples)
# on the first phase's kernel, uniform 4096^2 unpipelined; the CUDA tests.
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
B=.devrun/expanse_bench_cuda
for round in 1 2; do
  timeout 100 .devrun/baseline/expanse_bench_cuda --sizes 4096 --dists uniform,kuzmin,gaussian --reps 5 | tag base
  timeout 100 $B --sizes 4096 --dists uniform,kuzmin,gaussian --reps 5 | tag "HEAD one walk"
  EXPANSE_CUDA_INBOX_WALKS=2 timeout 100 $B --sizes 4096 --dists uniform,kuzmin,gaussian --reps 5 | tag "HEAD two walks"
done
python3 - $J <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'], r['side'], r['variant'])].append('%.2f (stars %.2f, def %d)'%(g,s.get('stars',0),r['deferred']))
for k in sorted(d): print(*k, ' / '.join(d[k]))
PY
for v in "base .devrun/baseline/expanse_bench_cuda 1" "one $B 1" "two $B 2"; do
  set -- $v
  for dist in uniform kuzmin; do
    echo "== $1 $dist"; EXPANSE_CUDA_INBOX_WALKS=$3 EXPANSE_CUDA_STAR_TIMELINE=1 timeout 40 $2 --sizes 4096 --dists $dist --reps 3 2>&1 >/dev/null | grep "star stage timeline" | tail -1
  done
done | tee $OUT/call4-timelines.txt
timeout 150 .devrun/expanse_cuda_tests > $OUT/call4-cuda-tests.log 2>&1; echo "cuda tests rc $?"; grep -E "^FAIL|FAILED" $OUT/call4-cuda-tests.log | head -5; tail -1 $OUT/call4-cuda-tests.log
N=/usr/local/cuda/bin/ncu
timeout 200 $N -k regex:"^star_kernel$" --launch-skip 1 --launch-count 1 --section SourceCounters --section WarpStateStats --section LaunchStats --section Occupancy \
  --page source --print-source sass --csv $B --sizes 4096 --dists uniform --reps 1 --no-pipeline > $OUT/call4-ncu-sass.csv 2> $OUT/call4-ncu-stderr.txt
echo "ncu rc $?"; wc -c $OUT/call4-ncu-sass.csv; head -c 600 $OUT/call4-ncu-sass.csv; tail -3 $OUT/call4-ncu-stderr.txt
xz -T4 $OUT/call4-ncu-sass.csv 2>/dev/null; ls -la $OUT
