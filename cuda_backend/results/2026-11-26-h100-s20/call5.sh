#!/usr/bin/env bash
# Session 20 call 5: 6 blocks a multiprocessor on uniform cells by default (call 4: 4096^2
# uniform 39.15 -> 38.63 ms, 2048^2 18.47 -> 16.95, 1024^2 5.13 -> 4.92, 512^2 2.63 -> 2.58;
# predicted the same here, quantile inputs unchanged) against bb36602 (.devrun/baseline/); and
# 5 and 4 blocks (96 and 128 registers) on uniform 1024^2..4096^2 and kuzmin 4096^2, to see whether
# the trend goes on. Two rounds alternated; CUDA tests, memcheck, conformance.
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT .devrun/baseline/COMMIT
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $OUT/call5-blocks.jsonl; }
A="--sizes 4096 --dists uniform,gaussian,grid,kuzmin --reps 5"
S="--sizes 512,1024,2048 --dists uniform --reps 9"
T="--sizes 1024,2048,4096 --dists uniform,kuzmin --reps 5"
for round in 1 2; do
  timeout 150 .devrun/baseline/expanse_bench_cuda $A | tag base-$round
  timeout 150 .devrun/expanse_bench_cuda $A | tag new-$round
  timeout 60 .devrun/baseline/expanse_bench_cuda $S | tag base-$round
  timeout 60 .devrun/expanse_bench_cuda $S | tag new-$round
  EXPANSE_CUDA_BLOCKS_PER_SM=5 timeout 100 .devrun/expanse_bench_cuda $T | tag blocks5-$round
  EXPANSE_CUDA_BLOCKS_PER_SM=4 timeout 100 .devrun/expanse_bench_cuda $T | tag blocks4-$round
done
python3 - $OUT/call5-blocks.jsonl <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'],r['side'],r['variant'].rsplit('-',1)[0])].append('%.2f (stars %.2f) h2h %.1f seam %.4f%% def %d tri %d'%(g,s.get('stars',0),r.get('host_to_host_ms',0),100*r.get('seam_share',0),r['deferred'],r['triangles']))
for k in sorted(d): print(k, ' | '.join(d[k]))
PY
timeout 90 .devrun/expanse_cuda_tests > $OUT/call5-cuda-tests.log 2>&1; echo "cuda tests rc $?"; tail -1 $OUT/call5-cuda-tests.log
timeout 90 /usr/local/cuda/bin/compute-sanitizer --tool memcheck --error-exitcode 9 .devrun/expanse_cuda_tests --small > $OUT/call5-memcheck.log 2>&1; echo "memcheck rc $?"; tail -1 $OUT/call5-memcheck.log
timeout 150 .devrun/expanse_conformance --backend cuda > $OUT/call5-conformance.log 2>&1; echo "conformance rc $?"; tail -2 $OUT/call5-conformance.log
