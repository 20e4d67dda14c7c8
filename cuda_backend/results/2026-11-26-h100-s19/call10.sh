#!/usr/bin/env bash
# Session 19 call 10: no compaction where no point repeats (the sorted points and their input
# indices become the sites by a swap of buffers; call 8 timed the copy at 0.27 ms at 4096^2)
# against e9d05a0's code (.devrun/baseline/). Predicted -0.25 ms GPU-only at 4096^2 on inputs
# without repeats; duplicates unchanged (their compaction now after the count's read-back).
# 4096^2 uniform, gaussian, grid, kuzmin, 2048^2 duplicates; two rounds alternated; CUDA tests,
# the four sanitizers, conformance on CUDA.
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $OUT/call10-compact.jsonl; }
A="--sizes 4096 --dists uniform,gaussian,grid,kuzmin --reps 5"
D="--sizes 2048 --dists duplicates --reps 5"
for round in 1 2; do
  timeout 150 .devrun/baseline/expanse_bench_cuda $A | tag baseline-$round
  timeout 150 .devrun/expanse_bench_cuda $A | tag current-$round
  timeout 60 .devrun/baseline/expanse_bench_cuda $D | tag baseline-$round
  timeout 60 .devrun/expanse_bench_cuda $D | tag current-$round
done
python3 - $OUT/call10-compact.jsonl <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'],r['side'],r['variant'].rsplit('-',1)[0])].append('%.2f (stars %.2f merge %.2f compact %.2f) h2h %.1f sites %d def %d tri %d'%(g,s.get('stars',0),s.get('merge duplicates',0),s.get('compact',0),r.get('host_to_host_ms',0),r['sites'],r['deferred'],r['triangles']))
for k in sorted(d): print(k, ' | '.join(d[k]))
PY
timeout 90 .devrun/expanse_cuda_tests > $OUT/call10-cuda-tests.log 2>&1; echo "cuda tests rc $?"; grep "device preparation" $OUT/call10-cuda-tests.log | head -12; tail -1 $OUT/call10-cuda-tests.log
for tool in memcheck initcheck synccheck racecheck; do
  timeout 90 /usr/local/cuda/bin/compute-sanitizer --tool $tool --error-exitcode 9 .devrun/expanse_cuda_tests --small > /tmp/san.log 2>&1; echo "$tool rc $?"; tail -1 /tmp/san.log; (echo "=== $tool"; cat /tmp/san.log) >> $OUT/call10-sanitizers.log
done
timeout 150 .devrun/expanse_conformance --backend cuda > $OUT/call10-conformance.log 2>&1; echo "conformance rc $?"; tail -2 $OUT/call10-conformance.log
