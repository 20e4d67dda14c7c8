#!/usr/bin/env bash
# Session 24 call 3: the boundary strips (BoundaryStrips) and the long edges' first box along the
# edge, in the edge's walks and the warps' second pass. Counted on the CPU, the hull-hugging
# sites' thin regions along the square's sides were 24.4 M of the 26.0 M units of 4096^2 uniform's
# sites over 2^10; call 1 found the edge's stream costing the first phase 2.4 ms (uniform) to 3.3
# (kuzmin). Expected: uniform's edge retry far shorter, its first phase -1 to -2 ms, fewer
# deferred sites; kuzmin and gaussian (quantile cells, no long-edge box) little change.
# Against e8191a3 (call 2's build: session 23's code with the experiments' switches) on the same
# machine, and EXPANSE_CUDA_STRIPS=0 in the same build; two rounds; 512^2 and 2048^2; timelines;
# CUDA tests, four sanitizers, conformance.
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT .devrun/baseline/COMMIT
J=$OUT/call3-strips.jsonl
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
  EXPANSE_CUDA_STRIPS=0 timeout 150 $B --sizes 4096 --dists uniform,kuzmin --reps 5 | tag strips0
done
timeout 100 $B --sizes 512,2048 --dists uniform,kuzmin --reps 7 | tag strips
timeout 100 .devrun/baseline/expanse_bench_cuda --sizes 512,2048 --dists uniform,kuzmin --reps 7 | tag base
python3 - $J <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'], r['side'], r['variant'])].append('%.2f (stars %.2f, bucket %.2f, def %d, h2h %.1f)'%(g,s.get('stars',0),s.get('bucket',0),r['deferred'],r.get('host_to_host_ms',0)))
for k in sorted(d): print(*k, ' / '.join(d[k]))
PY
for v in 1 0; do for dist in uniform kuzmin; do
  echo "== timeline strips=$v $dist"
  EXPANSE_CUDA_STRIPS=$v EXPANSE_CUDA_STAR_TIMELINE=1 timeout 60 $B --sizes 4096 --dists $dist --reps 2 2>&1 >/dev/null | grep "star stage" | tail -2
done; done > $OUT/call3-timeline.txt 2>&1
cat $OUT/call3-timeline.txt
timeout 200 .devrun/expanse_cuda_tests > $OUT/call3-cuda-tests.log 2>&1; echo "cuda tests rc $?"; tail -1 $OUT/call3-cuda-tests.log; grep -i "strips" $OUT/call3-cuda-tests.log | head -12
for tool in memcheck racecheck initcheck synccheck; do
  timeout 150 /usr/local/cuda/bin/compute-sanitizer --tool $tool --error-exitcode 9 .devrun/expanse_cuda_tests --small > /tmp/san.log 2>&1; echo "$tool rc $?"; tail -1 /tmp/san.log; (echo "=== $tool"; cat /tmp/san.log) >> $OUT/call3-sanitizers.log
done
timeout 150 .devrun/expanse_conformance --backend cuda > $OUT/call3-conformance.log 2>&1; echo "conformance rc $?"; tail -2 $OUT/call3-conformance.log
