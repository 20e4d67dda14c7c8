#!/usr/bin/env bash
# Session 30 call 6: F (the bundle's build, the final code: the edge's retry on the low stream, 2
# blocks a multiprocessor, lattices as before) against session 29's final code (baseline/, e15dfa3
# built at a87fdb5): 4096^2 every input, two rounds alternated; 512^2 to 2048^2 one round;
# timelines; F's CUDA tests, the conformance suite on CUDA, compute-sanitizer's four tools on the
# CUDA tests' small cases.
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
B=.devrun/expanse_bench_cuda O=.devrun/baseline/expanse_bench_cuda
for round in 1 2; do
  timeout 150 $B --sizes 4096 --dists uniform,gaussian,grid,kuzmin --reps 5 | tag F
  timeout 150 $O --sizes 4096 --dists uniform,gaussian,grid,kuzmin --reps 5 | tag base
done
timeout 100 $B --sizes 512,1024,2048 --dists uniform,gaussian,grid,kuzmin --reps 7 | tag F
timeout 100 $O --sizes 512,1024,2048 --dists uniform,gaussian,grid,kuzmin --reps 7 | tag base
python3 - $J <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'], r['side'], r['variant'])].append('%.2f (stars %.2f, def %d, seam %.4f%%, h2h %.1f)'%(g,s.get('stars',0),r['deferred'],100*r.get('seam_share',0),r.get('host_to_host_ms',0)))
for k in sorted(d): print(*k, ' / '.join(d[k]))
PY
for dist in kuzmin uniform; do
  echo "== $dist F"; EXPANSE_CUDA_STAR_TIMELINE=1 timeout 60 $B --sizes 4096 --dists $dist --reps 2 2>&1 >/dev/null | grep "star stage" | tail -2
done | tee $OUT/call6-timelines.txt
timeout 150 .devrun/expanse_cuda_tests > $OUT/call6-cuda-tests.log 2>&1; echo "cuda tests rc $?"; grep -E "^FAIL" $OUT/call6-cuda-tests.log | head; tail -1 $OUT/call6-cuda-tests.log
grep -c "^ok   edge retry" $OUT/call6-cuda-tests.log
timeout 170 .devrun/expanse_conformance --backend cuda > $OUT/call6-conformance.log 2>&1; echo "conformance rc $?"; tail -2 $OUT/call6-conformance.log
for tool in memcheck initcheck synccheck racecheck; do
  timeout 60 /usr/local/cuda/bin/compute-sanitizer --tool $tool --error-exitcode 9 .devrun/expanse_cuda_tests --small > /tmp/san.log 2>&1; echo "$tool rc $?"; tail -1 /tmp/san.log; (echo "=== $tool"; cat /tmp/san.log) >> $OUT/call6-sanitizers.log
done
