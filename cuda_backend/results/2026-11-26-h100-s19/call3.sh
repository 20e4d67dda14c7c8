#!/usr/bin/env bash
# Session 19 call 3: the thread walk's candidate loop flattened into the scan loop (one candidate
# a pass; EXPANSE_CUDA_FLAT_SCAN=1, this build) against the nested loops (.devrun/baseline/, the
# build of call 1, f399f32), 512^2 .. 4096^2 uniform and 4096^2 kuzmin, gaussian, grid; and the
# small first box (0.75,0.5), faster at 512^2 in call 1, at 512^2 and 1024^2 on the baseline.
# Two rounds alternated; CUDA tests and memcheck on this build.
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $OUT/call3-flat.jsonl; }
A="--sizes 512,2048,4096 --dists uniform --reps 5"
Q="--sizes 4096 --dists kuzmin,gaussian,grid --reps 5"
S="--sizes 512,1024 --dists uniform,gaussian --reps 9"
for round in 1 2; do
  timeout 60 .devrun/baseline/expanse_bench_cuda $A | tag nested-$round
  timeout 60 .devrun/expanse_bench_cuda $A | tag flat-$round
  timeout 90 .devrun/baseline/expanse_bench_cuda $Q | tag nested-$round
  timeout 90 .devrun/expanse_bench_cuda $Q | tag flat-$round
  timeout 60 .devrun/baseline/expanse_bench_cuda $S | tag small-nested-fb1,1-$round
  EXPANSE_CUDA_FIRST_BOX=0.75,0.5 timeout 60 .devrun/baseline/expanse_bench_cuda $S | tag small-nested-fb0.75,0.5-$round
done
python3 - $OUT/call3-flat.jsonl <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'],r['side'],r['variant'].rsplit('-',1)[0])].append('%.2f (stars %.2f) pred %.1f def %d tri %d'%(g,s.get('stars',0),r['predicates']/r['n'],r['deferred'],r['triangles']))
for k in sorted(d): print(k, ' | '.join(d[k]))
PY
timeout 60 .devrun/expanse_cuda_tests > $OUT/call3-cuda-tests.log 2>&1; echo "cuda tests rc $?"; tail -1 $OUT/call3-cuda-tests.log
timeout 60 /usr/local/cuda/bin/compute-sanitizer --tool memcheck --error-exitcode 9 .devrun/expanse_cuda_tests --small > $OUT/call3-memcheck.log 2>&1; echo "memcheck rc $?"; tail -1 $OUT/call3-memcheck.log
