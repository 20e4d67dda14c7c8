#!/usr/bin/env bash
# Session 27 call 8: F (the bundle's build): the lattices' kernels branch on the boundaries alone,
# as with the uniform copy alone (call 2), against D (variantD/, 1ab934b); grid, uniform and
# kuzmin 4096^2 and the grid at 512^2 to 2048^2; F's CUDA tests, four sanitizers, conformance.
set -u
bash bench/device/run-on-device.sh env > $OUT/call8-env.txt 2>&1
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT .devrun/variantD/COMMIT
J=$OUT/call8-lattice.jsonl
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $J; }
F=.devrun/expanse_bench_cuda D=.devrun/variantD/expanse_bench_cuda
timeout 60 $F --sizes 4096 --dists grid,uniform,kuzmin --reps 5 | tag F
timeout 60 $D --sizes 4096 --dists grid,uniform,kuzmin --reps 5 | tag D
timeout 60 $F --sizes 512,1024,2048,4096 --dists grid --reps 5 | tag F
timeout 60 $D --sizes 512,1024,2048 --dists grid --reps 5 | tag D
python3 - $J <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'], r['side'], r['variant'])].append('%.2f (stars %.2f, def %d, seam %.4f%%)'%(g,s.get('stars',0),r['deferred'],100*r.get('seam_share',0)))
for k in sorted(d): print(*k, ' / '.join(d[k]))
PY
timeout 100 .devrun/expanse_cuda_tests > $OUT/call8-cuda-tests.log 2>&1; echo "cuda tests rc $?"; tail -1 $OUT/call8-cuda-tests.log
for tool in memcheck racecheck initcheck synccheck; do
  timeout 60 /usr/local/cuda/bin/compute-sanitizer --tool $tool --error-exitcode 9 .devrun/expanse_cuda_tests --small > /tmp/san.log 2>&1; echo "$tool rc $?"; tail -1 /tmp/san.log; (echo "=== $tool"; cat /tmp/san.log) >> $OUT/call8-sanitizers.log
done
timeout 60 .devrun/expanse_conformance --backend cuda > $OUT/call8-conformance.log 2>&1; echo "conformance rc $?"; tail -2 $OUT/call8-conformance.log
