#!/usr/bin/env bash
# Session 17 call 3: call 2's build without the emit's owners (the merge's hash tables per run,
# the scale folded in) against 6e8dc09, alternated, two rounds; the star stage's timeline
# (EXPANSE_CUDA_STAR_TIMELINE=1: when each stream's passes end) at 2048^2 and 4096^2; the
# edge's depth (EXPANSE_CUDA_EDGE_DEPTH 1 / 2 / 3); the CUDA tests.
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT .devrun/baseline/COMMIT
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $OUT/call3-compare.jsonl; }
for round in 1 2; do
  timeout 100 .devrun/baseline/expanse_bench_cuda --sizes 1024,2048,4096 --dists uniform,kuzmin,gaussian,grid --reps 5 | tag base-$round
  timeout 100 .devrun/expanse_bench_cuda --sizes 1024,2048,4096 --dists uniform,kuzmin,gaussian,grid --reps 5 | tag new-$round
done
for depth in 1 2 3 0; do
  EXPANSE_CUDA_EDGE_DEPTH=$depth EXPANSE_CUDA_STAR_TIMELINE=1 timeout 100 .devrun/expanse_bench_cuda --sizes 2048,4096 --dists uniform,kuzmin,gaussian --reps 5 2> /tmp/timeline.txt | tag depth$depth-1
  (echo "=== depth $depth"; grep timeline /tmp/timeline.txt) >> $OUT/call3-timeline.txt
done
python3 - $OUT/call3-compare.jsonl <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'],r['side'],r['variant'].split('-')[0])].append('%.2f (sort %.2f merge %.2f emit %.2f bucket %.2f stars %.2f) h2h %.1f tri %d def %d'%(g,s.get('sort',0),s.get('merge duplicates',0),s.get('emit',0),s.get('bucket',0),s.get('stars',0),r.get('host_to_host_ms',0),r['triangles'],r['deferred']))
for k in sorted(d): print(k, ' | '.join(d[k]))
PY
awk '/===/{print; n=0; next} {n++; if (n%6==0) print}' $OUT/call3-timeline.txt | cut -c1-400
timeout 200 .devrun/expanse_cuda_tests > $OUT/call3-cuda-tests.log 2>&1; echo "cuda tests rc $?"; tail -1 $OUT/call3-cuda-tests.log
