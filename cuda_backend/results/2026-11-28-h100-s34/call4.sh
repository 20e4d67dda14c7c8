#!/usr/bin/env bash
# Session 34 call 4: HEAD (the leaner candidate loop of call 2, cf46e45) against session 32's code
# (baseline/, ffeff5d) at 512^2 .. 4096^2, two rounds at 4096^2; the star kernels' blocks a
# multiprocessor again (EXPANSE_CUDA_BLOCKS_PER_SM, 4096^2 uniform); the CUDA tests; ncu's source
# counters on the first phase's kernel (uniform 4096^2, unpipelined), as session 33 call 4.
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
B=.devrun/expanse_bench_cuda; BASE=.devrun/baseline/expanse_bench_cuda
timeout 120 $BASE --sizes 4096 --dists uniform,gaussian,grid,kuzmin --reps 5 | tag base
timeout 120 $B --sizes 4096 --dists uniform,gaussian,grid,kuzmin --reps 5 | tag HEAD
timeout 120 $B --sizes 4096 --dists uniform,gaussian,grid,kuzmin --reps 5 | tag HEAD
timeout 120 $BASE --sizes 4096 --dists uniform,gaussian,grid,kuzmin --reps 5 | tag base
for v in base HEAD; do b=$B; [ $v = base ] && b=$BASE; timeout 100 $b --sizes 512,1024,2048 --dists uniform,gaussian,grid,kuzmin --reps 7 | tag $v; done
for s in 8,8,6 8,6,8 8,8,8 8,6,6; do EXPANSE_CUDA_BLOCKS_PER_SM=$s timeout 60 $B --sizes 4096 --dists uniform --reps 5 | tag "HEAD $s"; done
python3 - $J <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'], r['side'], r['variant'])].append('%.2f (stars %.2f, def %d, seam %.5f%%, h2h %.1f)'%(g,s.get('stars',0),r['deferred'],100*r.get('seam_share',0),r.get('host_to_host_ms',0)))
for k in sorted(d): print(*k, ' / '.join(d[k]))
PY
echo "== HEAD uniform"; EXPANSE_CUDA_STAR_TIMELINE=1 timeout 40 $B --sizes 4096 --dists uniform --reps 3 2>&1 >/dev/null | grep "star stage timeline" | tail -1 | tee $OUT/call4-timelines.txt
timeout 150 .devrun/expanse_cuda_tests > $OUT/call4-cuda-tests.log 2>&1; echo "cuda tests rc $?"; grep -E "^FAIL|FAILED" $OUT/call4-cuda-tests.log | head -5; tail -1 $OUT/call4-cuda-tests.log
N=/usr/local/cuda/bin/ncu
timeout 200 $N -k regex:"^star_kernel$" --launch-skip 1 --launch-count 1 --section SourceCounters --section WarpStateStats --section LaunchStats --section Occupancy \
  --page source --print-source sass --csv $B --sizes 4096 --dists uniform --reps 1 --no-pipeline > $OUT/call4-ncu-sass.csv 2> $OUT/call4-ncu-stderr.txt
echo "ncu rc $?"; wc -c $OUT/call4-ncu-sass.csv; tail -2 $OUT/call4-ncu-stderr.txt
xz -T4 $OUT/call4-ncu-sass.csv 2>/dev/null; [ -s $OUT/call4-ncu-stderr.txt ] || rm -f $OUT/call4-ncu-stderr.txt; ls -la $OUT
