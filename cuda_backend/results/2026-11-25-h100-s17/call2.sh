#!/usr/bin/env bash
# Session 17 call 2: the merge's hash tables one per run of equal codes, the scale folded into
# the codes and the gather, and the emit's owners written in order (working tree over 6e8dc09)
# against 6e8dc09, alternated, two rounds, 512^2-4096^2, four inputs; CUDA tests (a new case: a
# cluster finer than the quantisation, with copies); conformance on CUDA, one and two phases;
# the four sanitizers; ncu durations of the kernels outside the star walks at 4096^2.
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT .devrun/baseline/COMMIT
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $OUT/call2-compare.jsonl; }
for round in 1 2; do
  timeout 100 .devrun/baseline/expanse_bench_cuda --sizes 512,1024,2048,4096 --dists uniform,kuzmin,gaussian,grid --reps 5 | tag base-$round
  timeout 100 .devrun/expanse_bench_cuda --sizes 512,1024,2048,4096 --dists uniform,kuzmin,gaussian,grid --reps 5 | tag new-$round
done
python3 - $OUT/call2-compare.jsonl <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'],r['side'],r['variant'].split('-')[0])].append('%.2f (sort %.2f merge %.2f emit %.2f stars %.2f) h2h %.1f tri %d def %d'%(g,s.get('sort',0),s.get('merge duplicates',0),s.get('emit',0),s.get('stars',0),r.get('host_to_host_ms',0),r['triangles'],r['deferred']))
for k in sorted(d): print(k, ' | '.join(d[k]))
PY
timeout 200 .devrun/expanse_cuda_tests > $OUT/call2-cuda-tests.log 2>&1; echo "cuda tests rc $?"; grep -i "cluster finer\|FAIL" $OUT/call2-cuda-tests.log; tail -1 $OUT/call2-cuda-tests.log
timeout 200 .devrun/expanse_conformance --backend cuda > $OUT/call2-conformance.log 2>&1; echo "conformance rc $?"; tail -2 $OUT/call2-conformance.log
EXPANSE_CUDA_PHASES=2 timeout 200 .devrun/expanse_conformance --backend cuda >> $OUT/call2-conformance.log 2>&1; echo "conformance (two phases) rc $?"; tail -2 $OUT/call2-conformance.log
for tool in memcheck racecheck initcheck synccheck; do
  timeout 120 /usr/local/cuda/bin/compute-sanitizer --tool $tool --error-exitcode 9 .devrun/expanse_cuda_tests --small > /tmp/san.log 2>&1; echo "$tool rc $?"; tail -1 /tmp/san.log; (echo "=== $tool"; cat /tmp/san.log) >> $OUT/call2-sanitizers.log
done
for dist in uniform kuzmin; do
  for v in baseline/ ""; do
    timeout 100 /usr/local/cuda/bin/ncu --kernel-name regex:'emit|gather|morton|scale|hash|run_|first_equal|long_run|compact|Radix|Scan|Onesweep|Histogram|audit' --launch-count 40 --metrics gpu__time_duration.sum --print-summary per-kernel .devrun/${v}expanse_bench_cuda --sizes 4096 --dists $dist --reps 1 > /tmp/ncu.txt 2>&1 || echo "ncu $dist $v failed"; (echo "=== $dist ${v:-new}"; cat /tmp/ncu.txt) >> $OUT/call2-ncu.txt
  done
done
grep -E "^===|^  [A-Za-z_].*\(|gpu__time_duration" $OUT/call2-ncu.txt | head -150
