#!/usr/bin/env bash
# Session 20 call 9: the final code. Block counts a multiprocessor by kernel group (StarBlocks):
# uniform cells up to 2^22 sites 4,4,4, above 8,6,6; quantile cells 8,6,8; integer sites 6,6,6.
# Against bb36602 (.devrun/baseline/), every distribution at 512^2..4096^2, two rounds
# alternated. Predicted from calls 5-8: uniform 4096^2 39.1 -> 37.7 ms, 2048^2 18.3 -> 15.4,
# 1024^2 5.1 -> 4.55, 512^2 2.62 -> 2.5; gaussian 4096^2 48.4 -> 47.7; kuzmin and grid unchanged.
# Then kuzmin 4096^2 8,8,8 against the default 8,6,8 in three more rounds (call 8 could not tell),
# CUDA tests, the four sanitizers, conformance on CUDA.
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT .devrun/baseline/COMMIT
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $OUT/call9-final.jsonl; }
A="--sizes 512,1024,2048,4096 --dists uniform,gaussian,grid,kuzmin --reps 5"
for round in 1 2; do
  timeout 280 .devrun/baseline/expanse_bench_cuda $A | tag base-$round
  timeout 280 .devrun/expanse_bench_cuda $A | tag new-$round
done
python3 - $OUT/call9-final.jsonl <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'],r['side'],r['variant'].rsplit('-',1)[0])].append('%.2f (stars %.2f) h2h %.1f seam %.4f%% def %d tri %d'%(g,s.get('stars',0),r.get('host_to_host_ms',0),100*r.get('seam_share',0),r['deferred'],r['triangles']))
for k in sorted(d): print(k, ' | '.join(d[k]))
PY
for round in 1 2 3; do
  EXPANSE_CUDA_BLOCKS_PER_SM=8,8,8 timeout 60 .devrun/expanse_bench_cuda --sizes 4096 --dists kuzmin --reps 5 | tag kuzmin888-$round
  timeout 60 .devrun/expanse_bench_cuda --sizes 4096 --dists kuzmin --reps 5 | tag kuzmin868-$round
done
python3 - $OUT/call9-final.jsonl <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  if not r['variant'].startswith('kuzmin8'): continue
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[r['variant'].rsplit('-',1)[0]].append('%.2f'%g)
for k in sorted(d): print(k, ' '.join(d[k]))
PY
timeout 90 .devrun/expanse_cuda_tests > $OUT/call9-cuda-tests.log 2>&1; echo "cuda tests rc $?"; tail -1 $OUT/call9-cuda-tests.log
for v in 8,6,6 8,6,8; do EXPANSE_CUDA_BLOCKS_PER_SM=$v timeout 90 .devrun/expanse_cuda_tests > /tmp/t.log 2>&1; echo "cuda tests (blocks $v) rc $?"; tail -1 /tmp/t.log; done
for tool in memcheck initcheck synccheck racecheck; do
  timeout 90 /usr/local/cuda/bin/compute-sanitizer --tool $tool --error-exitcode 9 .devrun/expanse_cuda_tests --small > /tmp/san.log 2>&1; echo "$tool rc $?"; tail -1 /tmp/san.log; (echo "=== $tool"; cat /tmp/san.log) >> $OUT/call9-sanitizers.log
done
timeout 150 .devrun/expanse_conformance --backend cuda > $OUT/call9-conformance.log 2>&1; echo "conformance rc $?"; tail -2 $OUT/call9-conformance.log
