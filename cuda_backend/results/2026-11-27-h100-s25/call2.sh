#!/usr/bin/env bash
# Session 25 call 2 (aed0ee5): quantile cells with heavy tails weighed 3x (quantile_tails), against
# EXPANSE_CUDA_TAILS=0 (plain quantiles) in the same binary, alternated, two rounds at 4096^2;
# e87804a (baseline/, session 24's build) once for the inputs that should not move.
# Expected (counted on the CPU: kuzmin 4096^2 work 89.5 -> 80.9 units a site, sites past 2^11
# units 21,761 -> 6,410): kuzmin's stars 57.7 -> ~53 ms (its edge stream and retry, the heavy
# sites' walks, shorter), GPU-only ~67 -> ~62; gaussian, uniform and grid unchanged (their axes
# are not heavy-tailed: plain quantiles or equal cells).
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT .devrun/baseline/COMMIT
J=$OUT/call2-tails.jsonl
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $J; }
B=.devrun/expanse_bench_cuda
for round in 1 2; do
  timeout 120 $B --sizes 4096 --dists kuzmin,gaussian --reps 5 | tag tails
  EXPANSE_CUDA_TAILS=0 timeout 120 $B --sizes 4096 --dists kuzmin,gaussian --reps 5 | tag plain
done
timeout 100 $B --sizes 4096 --dists uniform,grid --reps 5 | tag tails
timeout 100 .devrun/baseline/expanse_bench_cuda --sizes 4096 --dists uniform,grid,kuzmin --reps 5 | tag base
timeout 100 $B --sizes 512,1024,2048 --dists kuzmin --reps 7 | tag tails
EXPANSE_CUDA_TAILS=0 timeout 100 $B --sizes 512,1024,2048 --dists kuzmin --reps 7 | tag plain
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
for v in 1 0; do
  echo "== timeline kuzmin EXPANSE_CUDA_TAILS=$v"
  EXPANSE_CUDA_TAILS=$v EXPANSE_CUDA_STAR_TIMELINE=1 timeout 60 $B --sizes 4096 --dists kuzmin --reps 2 2>&1 >/dev/null | grep "star stage" | tail -2
done > $OUT/call2-timeline.txt 2>&1
cat $OUT/call2-timeline.txt
timeout 200 .devrun/expanse_cuda_tests > $OUT/call2-cuda-tests.log 2>&1; echo "cuda tests rc $?"; tail -1 $OUT/call2-cuda-tests.log
for tool in memcheck racecheck initcheck synccheck; do
  timeout 150 /usr/local/cuda/bin/compute-sanitizer --tool $tool --error-exitcode 9 .devrun/expanse_cuda_tests --small > /tmp/san.log 2>&1; echo "$tool rc $?"; tail -1 /tmp/san.log; (echo "=== $tool"; cat /tmp/san.log) >> $OUT/call2-sanitizers.log
done
timeout 150 .devrun/expanse_conformance --backend cuda > $OUT/call2-conformance.log 2>&1; echo "conformance rc $?"; tail -2 $OUT/call2-conformance.log
