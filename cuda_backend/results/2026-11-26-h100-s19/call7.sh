#!/usr/bin/env bash
# Session 19 call 7: the second phase in two kernels (an inbox pass, a thread per odd site, budget
# 16 units, that finishes the stars its posts complete and lists the rest, packed, for a thread
# each; default) against one kernel (EXPANSE_CUDA_PHASE_SPLIT=0). Predicted: uniform 4096^2 second
# phase 9.5 -> 8-8.5 ms, kuzmin 19 -> 14-16 (scipy counts: 38% / 74% of the odd sites need no
# search). 2048^2 and 4096^2, four inputs, two rounds alternated, the timeline on round 2; CUDA
# tests, the four sanitizers, conformance on CUDA.
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $OUT/call7-split.jsonl; }
B=".devrun/expanse_bench_cuda --sizes 2048,4096 --dists uniform,gaussian,grid,kuzmin --reps 5"
timeout 100 $B | tag split-1
EXPANSE_CUDA_PHASE_SPLIT=0 timeout 100 $B | tag one-1
EXPANSE_CUDA_STAR_TIMELINE=1 timeout 100 $B 2> /tmp/t1.txt | tag split-2
EXPANSE_CUDA_PHASE_SPLIT=0 EXPANSE_CUDA_STAR_TIMELINE=1 timeout 100 $B 2> /tmp/t2.txt | tag one-2
(echo "=== split round 2"; grep timeline /tmp/t1.txt; echo "=== one kernel round 2"; grep timeline /tmp/t2.txt) > $OUT/call7-timeline.txt
python3 - $OUT/call7-split.jsonl <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'],r['side'],r['variant'].rsplit('-',1)[0])].append('%.2f (stars %.2f) h2h %.1f def %d tri %d'%(g,s.get('stars',0),r.get('host_to_host_ms',0),r['deferred'],r['triangles']))
for k in sorted(d): print(k, ' | '.join(d[k]))
PY
timeout 90 .devrun/expanse_cuda_tests > $OUT/call7-cuda-tests.log 2>&1; echo "cuda tests rc $?"; tail -1 $OUT/call7-cuda-tests.log
for tool in memcheck initcheck synccheck racecheck; do
  timeout 90 /usr/local/cuda/bin/compute-sanitizer --tool $tool --error-exitcode 9 .devrun/expanse_cuda_tests --small > /tmp/san.log 2>&1; echo "$tool rc $?"; tail -1 /tmp/san.log; (echo "=== $tool"; cat /tmp/san.log) >> $OUT/call7-sanitizers.log
done
timeout 150 .devrun/expanse_conformance --backend cuda > $OUT/call7-conformance.log 2>&1; echo "conformance rc $?"; tail -2 $OUT/call7-conformance.log
