#!/usr/bin/env bash
# Session 20 call 1: the single-precision screen before the apex filters (default) against the
# double filters alone (EXPANSE_CUDA_SCREEN=off), same build, two rounds alternated.
# Predicted: the filters were 52% of the first phase's warp samples (session 18 ncu); the screen
# settles ~99.9% of candidates in ~45 FP32 operations where the filters took ~50 FP64 ones (FP32
# issues twice as fast on the H100), so star kernels -3 to -6 ms at 4096^2 uniform (32.5 ms),
# similar shares elsewhere; the same triangles, work and deferred sites either way.
# Also: the star kernels' registers and spills (cuobjdump), CUDA tests, memcheck, conformance.
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT
(cuobjdump -res-usage .devrun/expanse_bench_cuda 2>&1 | grep -A1 "star_kernel\|star_retry_kernel\|star_list_kernel" | grep -o "REG:[0-9]* STACK:[0-9]* SHARED:[0-9]* LOCAL:[0-9]*" | sort | uniq -c) > $OUT/call1-res-usage.txt
cat $OUT/call1-res-usage.txt | head -20
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $OUT/call1-screen.jsonl; }
A="--sizes 4096 --dists uniform,gaussian,grid,kuzmin --reps 5"
S="--sizes 512,1024 --dists uniform,kuzmin --reps 9"
for round in 1 2; do
  EXPANSE_CUDA_SCREEN=off timeout 150 .devrun/expanse_bench_cuda $A | tag off-$round
  timeout 150 .devrun/expanse_bench_cuda $A | tag screen-$round
  EXPANSE_CUDA_SCREEN=off timeout 60 .devrun/expanse_bench_cuda $S | tag off-$round
  timeout 60 .devrun/expanse_bench_cuda $S | tag screen-$round
done
python3 - $OUT/call1-screen.jsonl <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'],r['side'],r['variant'].rsplit('-',1)[0])].append('%.2f (stars %.2f) h2h %.1f pred %.2f def %d tri %d'%(g,s.get('stars',0),r.get('host_to_host_ms',0),r['predicates']/r['n'],r['deferred'],r['triangles']))
for k in sorted(d): print(k, ' | '.join(d[k]))
PY
timeout 90 .devrun/expanse_cuda_tests > $OUT/call1-cuda-tests.log 2>&1; echo "cuda tests rc $?"; tail -1 $OUT/call1-cuda-tests.log
timeout 90 /usr/local/cuda/bin/compute-sanitizer --tool memcheck --error-exitcode 9 .devrun/expanse_cuda_tests --small > $OUT/call1-memcheck.log 2>&1; echo "memcheck rc $?"; tail -1 $OUT/call1-memcheck.log
timeout 150 .devrun/expanse_conformance --backend cuda > $OUT/call1-conformance.log 2>&1; echo "conformance rc $?"; tail -2 $OUT/call1-conformance.log
