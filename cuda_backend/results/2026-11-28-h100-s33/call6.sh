#!/usr/bin/env bash
# Session 33 call 6: the best's lift kept in shared memory (BestLift: formed where the best
# changes, three 16-byte loads a candidate; HEAD) against session 32's final code (baseline/,
# ffeff5d); 4096^2 two rounds alternated, 512^2 and 2048^2; a timeline; the CUDA tests and
# compute-sanitizer's four tools on their small cases.
set -u
bash bench/device/run-on-device.sh env > /dev/null 2>&1; cp $OUT/env.txt $OUT/call6-env.txt 2>/dev/null; rm -f $OUT/env.txt
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT .devrun/baseline/COMMIT
J=$OUT/call6-compare.jsonl
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $J; }
declare -A BIN=([HEAD]=.devrun/expanse_bench_cuda [base]=.devrun/baseline/expanse_bench_cuda)
for v in base HEAD; do timeout 120 ${BIN[$v]} --sizes 4096 --dists uniform,gaussian,grid,kuzmin --reps 5 | tag $v; done
for v in base HEAD; do timeout 120 ${BIN[$v]} --sizes 4096 --dists uniform,kuzmin --reps 5 | tag $v; done
for v in base HEAD; do timeout 100 ${BIN[$v]} --sizes 512,2048 --dists uniform,gaussian,grid,kuzmin --reps 7 | tag $v; done
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
echo "== HEAD uniform"; EXPANSE_CUDA_STAR_TIMELINE=1 timeout 40 ${BIN[HEAD]} --sizes 4096 --dists uniform --reps 3 2>&1 >/dev/null | grep "star stage timeline" | tail -1 | tee $OUT/call6-timelines.txt
timeout 120 .devrun/expanse_cuda_tests > $OUT/call6-cuda-tests.log 2>&1; echo "cuda tests rc $?"; grep -E "^FAIL|FAILED" $OUT/call6-cuda-tests.log | head -5; tail -1 $OUT/call6-cuda-tests.log
for tool in memcheck racecheck initcheck synccheck; do
  timeout 60 /usr/local/cuda/bin/compute-sanitizer --tool $tool --error-exitcode 9 .devrun/expanse_cuda_tests --small > /tmp/san.log 2>&1; echo "$tool rc $?"; tail -1 /tmp/san.log; (echo "=== $tool"; cat /tmp/san.log) >> $OUT/call6-sanitizers.log
done
