#!/usr/bin/env bash
# Session 35 call 3: as call 2, the warp looking back together (one read a step for the warp; HEAD) against
# 4732f34 (baseline/, the hash tables past 65); 4096^2 two rounds alternated, 512^2..2048^2
# once; the merge's kernels in one kuzmin 4096^2 run (ncu); the CUDA tests; the sanitizers.
set -u
bash bench/device/run-on-device.sh env > /dev/null 2>&1; cp $OUT/env.txt $OUT/call3-env.txt 2>/dev/null; rm -f $OUT/env.txt
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT .devrun/baseline/COMMIT
J=$OUT/call3-compare.jsonl
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $J; }
B=.devrun/expanse_bench_cuda; BASE=.devrun/baseline/expanse_bench_cuda
timeout 120 $BASE --sizes 4096 --dists uniform,gaussian,grid,kuzmin --reps 5 | tag BASE
timeout 120 $B --sizes 4096 --dists uniform,gaussian,grid,kuzmin --reps 5 | tag HEAD
timeout 120 $B --sizes 4096 --dists uniform,gaussian,grid,kuzmin --reps 5 | tag HEAD
timeout 120 $BASE --sizes 4096 --dists uniform,gaussian,grid,kuzmin --reps 5 | tag BASE
for v in BASE HEAD; do b=$B; [ $v = BASE ] && b=$BASE; timeout 100 $b --sizes 512,1024,2048 --dists uniform,gaussian,grid,kuzmin --reps 7 | tag $v; done
python3 - $J <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'], r['side'], r['variant'])].append('%.2f (stars %.2f, merge %.2f, sort %.2f, def %d, seam %.5f%%, h2h %.1f)'%(g,s.get('stars',0),s.get('merge duplicates',0),s.get('sort',0),r['deferred'],100*r.get('seam_share',0),r.get('host_to_host_ms',0)))
for k in sorted(d): print(*k, ' / '.join(d[k]))
PY
timeout 100 /usr/local/cuda/bin/ncu --kernel-name regex:'first_equal|hash_|run_|long_run' --metrics gpu__time_duration.sum --csv $B --sizes 4096 --dists kuzmin --reps 1 2>/dev/null | grep -E '^"[0-9]' | awk -F'","' '{print $5, $NF}' | sed 's/(.*)//' | tee $OUT/call3-ncu-merge-kuzmin.txt
timeout 150 .devrun/expanse_cuda_tests > $OUT/call3-cuda-tests.log 2>&1; echo "cuda tests rc $?"; grep -E "^FAIL|FAILED" $OUT/call3-cuda-tests.log | head -5; grep -E "preparation" $OUT/call3-cuda-tests.log | head -20; tail -1 $OUT/call3-cuda-tests.log
for tool in memcheck racecheck initcheck synccheck; do
  timeout 70 /usr/local/cuda/bin/compute-sanitizer --tool $tool --error-exitcode 9 .devrun/expanse_cuda_tests --small > /tmp/san.log 2>&1; echo "$tool rc $?"; tail -1 /tmp/san.log; (echo "=== $tool"; cat /tmp/san.log) >> $OUT/call3-sanitizers.log
done
