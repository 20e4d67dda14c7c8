#!/usr/bin/env bash
# Session 18 call 3: the light phases' blocks of 128 threads (HEAD) against 64 and 32
# (EXPANSE_CUDA_STAR_THREADS): a block holds its multiprocessor slot until its slowest warp is
# done, and on kuzmin the slowest lanes are far slower (counted on the CPU). 512^2, 2048^2, 4096^2;
# uniform, kuzmin, gaussian (lattices keep their kernels); two rounds alternated, the timeline on
# round 2; CUDA tests, memcheck and racecheck with 32.
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $OUT/call3-threads.jsonl; }
B=".devrun/expanse_bench_cuda --sizes 512,2048,4096 --dists uniform,kuzmin,gaussian --reps 5"
for t in 128 32 64; do EXPANSE_CUDA_STAR_THREADS=$t timeout 60 $B | tag t$t-1; done
for t in 128 32 64; do
  EXPANSE_CUDA_STAR_THREADS=$t EXPANSE_CUDA_STAR_TIMELINE=1 timeout 60 $B 2> /tmp/t.txt | tag t$t-2
  (echo "=== threads $t round 2"; grep timeline /tmp/t.txt) >> $OUT/call3-timeline.txt
done
python3 - $OUT/call3-threads.jsonl <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'],r['side'],r['variant'].split('-')[0])].append('%.2f (stars %.2f) h2h %.1f def %d'%(g,s.get('stars',0),r.get('host_to_host_ms',0),r['deferred']))
for k in sorted(d): print(k, ' | '.join(d[k]))
PY
export EXPANSE_CUDA_STAR_THREADS=32
timeout 60 .devrun/expanse_cuda_tests > $OUT/call3-cuda-tests.log 2>&1; echo "cuda tests (32) rc $?"; tail -1 $OUT/call3-cuda-tests.log
for tool in memcheck racecheck; do
  timeout 60 /usr/local/cuda/bin/compute-sanitizer --tool $tool --error-exitcode 9 .devrun/expanse_cuda_tests --small > /tmp/san.log 2>&1; echo "$tool (32) rc $?"; tail -1 /tmp/san.log; (echo "=== $tool 32"; cat /tmp/san.log) >> $OUT/call3-sanitizers.log
done
