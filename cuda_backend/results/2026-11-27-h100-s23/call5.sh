#!/usr/bin/env bash
# Session 23 call 5: call 3's emit (emit 3.20 -> 2.50 ms at 4096^2 uniform) without call 4's
# places and padding (which cost the star kernels 0.25-0.5 ms), StarView loading only the
# star's own words (initcheck). Expected: call 3's numbers (uniform GPU-only ~35.55 ms, star
# kernels as the baseline's), initcheck clean. Against c3f9ffe, one round; CUDA tests, four
# sanitizers, conformance on CUDA.
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT .devrun/baseline/COMMIT
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $OUT/call5-emit.jsonl; }
for round in 1; do
  for v in new base; do
    B=.devrun/expanse_bench_cuda; [ $v = base ] && B=.devrun/baseline/expanse_bench_cuda
    timeout 150 $B --sizes 4096 --dists uniform,gaussian,grid,kuzmin --reps 5 | tag $v
    timeout 60 $B --sizes 512 --dists uniform --reps 7 | tag $v
  done
done
python3 - $OUT/call5-emit.jsonl <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'], r['side'], r['variant'])].append('%.2f (stars %.2f, emit %.2f, audit %.2f, h2h %.1f, tri %d, def %d)'%(g, s.get('stars',0), s.get('emit',0), s.get('audit',0), r.get('host_to_host_ms',0), r['triangles'], r['deferred']))
for k in sorted(d): print(*k, ' / '.join(d[k]))
PY
timeout 150 .devrun/expanse_cuda_tests > $OUT/call5-cuda-tests.log 2>&1; echo "cuda tests rc $?"; tail -1 $OUT/call5-cuda-tests.log
for tool in memcheck racecheck initcheck synccheck; do
  timeout 150 /usr/local/cuda/bin/compute-sanitizer --tool $tool --error-exitcode 9 .devrun/expanse_cuda_tests --small > /tmp/san.log 2>&1; echo "$tool rc $?"; tail -1 /tmp/san.log; (echo "=== $tool"; cat /tmp/san.log) >> $OUT/call5-sanitizers.log
done
timeout 150 .devrun/expanse_conformance --backend cuda > $OUT/call5-conformance.log 2>&1; echo "conformance rc $?"; tail -2 $OUT/call5-conformance.log
