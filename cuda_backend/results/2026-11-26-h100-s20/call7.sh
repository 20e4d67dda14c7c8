#!/usr/bin/env bash
# Session 20 call 7: the final rule (uniform cells of non-integer sites: 4 blocks a multiprocessor
# up to 2^22 sites, 6 above; quantile cells 8) against bb36602 (.devrun/baseline/), every
# distribution at 512^2..4096^2, two rounds alternated. Predicted from calls 4-6: uniform 512^2
# 2.63 -> 2.54 ms, 1024^2 5.10 -> 4.6, 2048^2 18.4 -> 15.6, 4096^2 39.2 -> 38.7; quantile inputs
# and grid unchanged. Then the stars' stream timeline at 4096^2 and 2048^2 uniform for 4, 6 and
# 8 blocks (which phases gain), CUDA tests, the four sanitizers, conformance on CUDA.
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT .devrun/baseline/COMMIT
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $OUT/call7-final.jsonl; }
A="--sizes 512,1024,2048,4096 --dists uniform,gaussian,grid,kuzmin --reps 5"
for round in 1 2; do
  timeout 280 .devrun/baseline/expanse_bench_cuda $A | tag base-$round
  timeout 280 .devrun/expanse_bench_cuda $A | tag new-$round
done
python3 - $OUT/call7-final.jsonl <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'],r['side'],r['variant'].rsplit('-',1)[0])].append('%.2f (stars %.2f) h2h %.1f seam %.4f%% def %d tri %d'%(g,s.get('stars',0),r.get('host_to_host_ms',0),100*r.get('seam_share',0),r['deferred'],r['triangles']))
for k in sorted(d): print(k, ' | '.join(d[k]))
PY
for b in 4 6 8; do for side in 2048 4096; do
  echo "== blocks $b side $side"; EXPANSE_CUDA_BLOCKS_PER_SM=$b EXPANSE_CUDA_STAR_TIMELINE=1 timeout 60 .devrun/expanse_bench_cuda --sizes $side --dists uniform --reps 3 2>&1 >/dev/null | grep -i timeline | tail -1
done; done > $OUT/call7-timeline.txt
cat $OUT/call7-timeline.txt
timeout 90 .devrun/expanse_cuda_tests > $OUT/call7-cuda-tests.log 2>&1; echo "cuda tests rc $?"; tail -1 $OUT/call7-cuda-tests.log
for tool in memcheck initcheck synccheck racecheck; do
  timeout 90 /usr/local/cuda/bin/compute-sanitizer --tool $tool --error-exitcode 9 .devrun/expanse_cuda_tests --small > /tmp/san.log 2>&1; echo "$tool rc $?"; tail -1 /tmp/san.log; (echo "=== $tool"; cat /tmp/san.log) >> $OUT/call7-sanitizers.log
done
timeout 150 .devrun/expanse_conformance --backend cuda > $OUT/call7-conformance.log 2>&1; echo "conformance rc $?"; tail -2 $OUT/call7-conformance.log
