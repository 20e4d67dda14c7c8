#!/usr/bin/env bash
# Session 18 call 1 (the only device time left: ~9 minutes). HEAD (d7cf4d9's default: the first
# pass's budget 2^12 on quantile cells above 2^23 sites) against EXPANSE_CUDA_EDGE_WALK=warp (the
# edge ring's sites walked straight by warps with the full budget, no first pass by threads),
# 2048^2 and 4096^2, four inputs, two rounds alternated (the timeline on round 2); warp edges at
# depth 2; CUDA tests and three sanitizers on both; racecheck on the default.
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT; uptime
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $OUT/call1-compare.jsonl; }
B=".devrun/expanse_bench_cuda --sizes 2048,4096 --dists uniform,kuzmin,gaussian,grid --reps 5"
timeout 80 $B | tag base-1
EXPANSE_CUDA_EDGE_WALK=warp timeout 80 $B | tag warp-1
EXPANSE_CUDA_STAR_TIMELINE=1 timeout 80 $B 2> /tmp/t-base.txt | tag base-2
EXPANSE_CUDA_EDGE_WALK=warp EXPANSE_CUDA_STAR_TIMELINE=1 timeout 80 $B 2> /tmp/t-warp.txt | tag warp-2
(echo "=== base round 2"; grep timeline /tmp/t-base.txt; echo "=== warp round 2"; grep timeline /tmp/t-warp.txt) > $OUT/call1-timeline.txt
EXPANSE_CUDA_EDGE_WALK=warp EXPANSE_CUDA_EDGE_DEPTH=2 timeout 60 .devrun/expanse_bench_cuda --sizes 4096 --dists uniform,kuzmin,gaussian --reps 5 | tag warpd2-1
python3 - $OUT/call1-compare.jsonl <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'],r['side'],r['variant'].split('-')[0])].append('%.2f (stars %.2f) h2h %.1f def %d seam %.6f'%(g,s.get('stars',0),r.get('host_to_host_ms',0),r['deferred'],r.get('seam_share',0)))
for k in sorted(d): print(k, ' | '.join(d[k]))
PY
timeout 60 .devrun/expanse_cuda_tests > $OUT/call1-cuda-tests.log 2>&1; echo "cuda tests rc $?"; tail -1 $OUT/call1-cuda-tests.log
EXPANSE_CUDA_EDGE_WALK=warp timeout 60 .devrun/expanse_cuda_tests > /tmp/w.log 2>&1; echo "cuda tests (warp edge) rc $?"; tail -1 /tmp/w.log; (echo "=== EXPANSE_CUDA_EDGE_WALK=warp"; cat /tmp/w.log) >> $OUT/call1-cuda-tests.log
for tool in memcheck initcheck synccheck racecheck; do
  for v in base warp; do
    [[ $tool == racecheck && $v == warp ]] && continue
    [[ $v == warp ]] && export EXPANSE_CUDA_EDGE_WALK=warp || unset EXPANSE_CUDA_EDGE_WALK
    timeout 60 /usr/local/cuda/bin/compute-sanitizer --tool $tool --error-exitcode 9 .devrun/expanse_cuda_tests --small > /tmp/san.log 2>&1; echo "$tool $v rc $?"; tail -1 /tmp/san.log; (echo "=== $tool $v"; cat /tmp/san.log) >> $OUT/call1-sanitizers.log
  done
done
unset EXPANSE_CUDA_EDGE_WALK
