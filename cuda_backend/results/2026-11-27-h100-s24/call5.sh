#!/usr/bin/env bash
# Session 24 call 5: call 4's code with the strips' arrays in the bucketing's unsorted keys and
# ids (no allocation of their own) and the strips' kernels compiled only where strips are built.
# Call 4 had kuzmin 4096^2 bucket 1.6 -> 2.7 ms and 512^2 / 2048^2 +0.7 / +1.5 ms GPU-only with no
# strip built (their allocation and their kernels' code alone). Expected: gaussian, kuzmin and
# the lattice back at e8191a3's times; uniform as call 4 (4096^2 35.0, 2048^2 11.9, 512^2 2.0
# ms). Two rounds at 4096^2; 512^2 and 2048^2; timelines; CUDA tests, four sanitizers, conformance.
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT .devrun/baseline/COMMIT
J=$OUT/call5-strips.jsonl
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $J; }
B=.devrun/expanse_bench_cuda
for round in 1 2; do
  timeout 150 $B --sizes 4096 --dists uniform,gaussian,grid,kuzmin --reps 5 | tag strips
  timeout 150 .devrun/baseline/expanse_bench_cuda --sizes 4096 --dists uniform,gaussian,grid,kuzmin --reps 5 | tag base
done
timeout 100 $B --sizes 512,2048 --dists uniform,kuzmin,grid --reps 7 | tag strips
timeout 100 .devrun/baseline/expanse_bench_cuda --sizes 512,2048 --dists uniform,kuzmin,grid --reps 7 | tag base
python3 - $J <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'], r['side'], r['variant'])].append('%.2f (stars %.2f, bucket %.2f, def %d, h2h %.1f, seam %.4f%%)'%(g,s.get('stars',0),s.get('bucket',0),r['deferred'],r.get('host_to_host_ms',0),100*r.get('seam_share',0)))
for k in sorted(d): print(*k, ' / '.join(d[k]))
PY
for dist in uniform gaussian; do
  echo "== timeline $dist"
  EXPANSE_CUDA_STAR_TIMELINE=1 timeout 60 $B --sizes 4096 --dists $dist --reps 2 2>&1 >/dev/null | grep "star stage" | tail -2
done > $OUT/call5-timeline.txt 2>&1
cat $OUT/call5-timeline.txt
timeout 200 .devrun/expanse_cuda_tests > $OUT/call5-cuda-tests.log 2>&1; echo "cuda tests rc $?"; tail -1 $OUT/call5-cuda-tests.log
for tool in memcheck racecheck initcheck synccheck; do
  timeout 150 /usr/local/cuda/bin/compute-sanitizer --tool $tool --error-exitcode 9 .devrun/expanse_cuda_tests --small > /tmp/san.log 2>&1; echo "$tool rc $?"; tail -1 /tmp/san.log; (echo "=== $tool"; cat /tmp/san.log) >> $OUT/call5-sanitizers.log
done
timeout 150 .devrun/expanse_conformance --backend cuda > $OUT/call5-conformance.log 2>&1; echo "conformance rc $?"; tail -2 $OUT/call5-conformance.log
