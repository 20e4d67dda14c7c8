#!/usr/bin/env bash
# Session 34 call 7: the apex loop loading the next candidate's point while it tests this one
# (HEAD, 074aac2) against call 6's HEAD (baseline/, 9e2958f); 4096^2 two rounds alternated
# (uniform and kuzmin twice more), 2048^2 once; a timeline; the CUDA tests.
set -u
bash bench/device/run-on-device.sh env > /dev/null 2>&1; cp $OUT/env.txt $OUT/call8-env.txt 2>/dev/null; rm -f $OUT/env.txt
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT .devrun/baseline/COMMIT
J=$OUT/call8-compare.jsonl
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $J; }
B=.devrun/expanse_bench_cuda; BASE=.devrun/baseline/expanse_bench_cuda
timeout 120 $BASE --sizes 4096 --dists uniform,gaussian,grid,kuzmin --reps 5 | tag U7
timeout 120 $B --sizes 4096 --dists uniform,gaussian,grid,kuzmin --reps 5 | tag HEAD
timeout 120 $B --sizes 4096 --dists uniform,gaussian,grid,kuzmin --reps 5 | tag HEAD
timeout 120 $BASE --sizes 4096 --dists uniform,gaussian,grid,kuzmin --reps 5 | tag U7
for v in U7 HEAD; do b=$B; [ $v = U7 ] && b=$BASE; timeout 100 $b --sizes 512,1024,2048 --dists uniform,gaussian,grid,kuzmin --reps 7 | tag $v; done
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
echo "== HEAD uniform"; EXPANSE_CUDA_STAR_TIMELINE=1 timeout 40 $B --sizes 4096 --dists uniform --reps 3 2>&1 >/dev/null | grep "star stage timeline" | tail -1 | tee $OUT/call8-timelines.txt
timeout 150 .devrun/expanse_cuda_tests > $OUT/call8-cuda-tests.log 2>&1; echo "cuda tests rc $?"; grep -E "^FAIL|FAILED" $OUT/call8-cuda-tests.log | head -5; tail -1 $OUT/call8-cuda-tests.log
for tool in memcheck racecheck initcheck synccheck; do
  timeout 70 /usr/local/cuda/bin/compute-sanitizer --tool $tool --error-exitcode 9 .devrun/expanse_cuda_tests --small > /tmp/san.log 2>&1; echo "$tool rc $?"; tail -1 /tmp/san.log; (echo "=== $tool"; cat /tmp/san.log) >> $OUT/call8-sanitizers.log
done
