#!/usr/bin/env bash
# Session 19 call 9: the long-run checks flag by warp (one atomic a warp, not one a point: call 8
# showed kuzmin's long_run_kernel at 0.28 ms, most of its points in long runs) against HEAD before
# it (.devrun/baseline/, e9d05a0's code); 4096^2 kuzmin, uniform, gaussian; two rounds alternated;
# CUDA tests and memcheck.
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $OUT/call9-flag.jsonl; }
A="--sizes 4096 --dists kuzmin,uniform,gaussian --reps 5"
for round in 1 2; do
  timeout 120 .devrun/baseline/expanse_bench_cuda $A | tag baseline-$round
  timeout 120 .devrun/expanse_bench_cuda $A | tag current-$round
done
python3 - $OUT/call9-flag.jsonl <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'],r['side'],r['variant'].rsplit('-',1)[0])].append('%.2f (stars %.2f sort %.2f merge %.2f) h2h %.1f def %d'%(g,s.get('stars',0),s.get('sort',0),s.get('merge duplicates',0),r.get('host_to_host_ms',0),r['deferred']))
for k in sorted(d): print(k, ' | '.join(d[k]))
PY
timeout 90 .devrun/expanse_cuda_tests > $OUT/call9-cuda-tests.log 2>&1; echo "cuda tests rc $?"; tail -1 $OUT/call9-cuda-tests.log
timeout 90 /usr/local/cuda/bin/compute-sanitizer --tool memcheck --error-exitcode 9 .devrun/expanse_cuda_tests --small > $OUT/call9-memcheck.log 2>&1; echo "memcheck rc $?"; tail -1 $OUT/call9-memcheck.log
