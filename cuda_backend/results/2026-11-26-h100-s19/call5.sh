#!/usr/bin/env bash
# Session 19 call 5: this build (call 4 with the forecast mended: one sampled point per stretch of the input, and up to one in 64 sharing a key; the small first box not on integer inputs) (the device preparation's short Morton sort, EXPANSE_CUDA_MORTON_SORT;
# the small first box on uniform cells up to 2^20 sites) against call 1's build
# (.devrun/baseline/, f399f32: the emit's known places already in both), 512^2 .. 4096^2, four
# inputs, two rounds alternated; the forced full sort on this build at 4096^2; then the CUDA
# tests, the four sanitizers on the small cases, and the conformance suite on CUDA.
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $OUT/call5-compare.jsonl; }
A="--sizes 512,1024,2048,4096 --dists uniform,gaussian,grid,kuzmin --reps 5"
for round in 1 2; do
  timeout 150 .devrun/baseline/expanse_bench_cuda $A | tag baseline-$round
  timeout 150 .devrun/expanse_bench_cuda $A | tag current-$round
  EXPANSE_CUDA_MORTON_SORT=full timeout 90 .devrun/expanse_bench_cuda --sizes 4096 --dists uniform,grid --reps 5 | tag fullsort-$round
done
python3 - $OUT/call5-compare.jsonl <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'],r['side'],r['variant'].rsplit('-',1)[0])].append('%.2f (stars %.2f sort %.2f merge %.2f emit %.2f) h2h %.1f short %s def %d'%(g,s.get('stars',0),s.get('sort',0),s.get('merge duplicates',0),s.get('emit',0),r.get('host_to_host_ms',0),r.get('short_morton_sort','-'),r['deferred']))
for k in sorted(d): print(k, ' | '.join(d[k]))
PY
timeout 90 .devrun/expanse_cuda_tests > $OUT/call5-cuda-tests.log 2>&1; echo "cuda tests rc $?"; grep -c "^ok" $OUT/call5-cuda-tests.log; grep "FAIL\|device preparation, " $OUT/call5-cuda-tests.log | head -12; tail -1 $OUT/call5-cuda-tests.log
for tool in memcheck initcheck synccheck racecheck; do
  timeout 90 /usr/local/cuda/bin/compute-sanitizer --tool $tool --error-exitcode 9 .devrun/expanse_cuda_tests --small > /tmp/san.log 2>&1; echo "$tool rc $?"; tail -1 /tmp/san.log; (echo "=== $tool"; cat /tmp/san.log) >> $OUT/call5-sanitizers.log
done
timeout 150 .devrun/expanse_conformance --backend cuda > $OUT/call5-conformance.log 2>&1; echo "conformance rc $?"; tail -2 $OUT/call5-conformance.log
