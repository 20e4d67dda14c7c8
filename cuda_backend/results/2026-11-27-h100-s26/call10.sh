#!/usr/bin/env bash
# Session 26 call 10: long_run_kernel with one atomic a warp against call 7's build (baseline/,
# c77244f): kuzmin and uniform 4096^2, two rounds alternated (kuzmin's merge should lose about
# 0.2 ms, uniform nothing: it takes the short sort, which needs no such check); CUDA tests,
# memcheck and racecheck.
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT .devrun/baseline/COMMIT
J=$OUT/call10-long-run.jsonl
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $J; }
D="--sizes 4096 --dists uniform,kuzmin --reps 5"
for round in 1 2; do
  timeout 100 .devrun/expanse_bench_cuda $D | tag final
  timeout 100 .devrun/baseline/expanse_bench_cuda $D | tag base
done
python3 - $J <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'], r['side'], r['variant'])].append('%.2f (merge %.2f, sort %.2f, stars %.2f, h2h %.1f)'%(g,s.get('merge duplicates',0),s.get('sort',0),s.get('stars',0),r.get('host_to_host_ms',0)))
for k in sorted(d): print(*k, ' / '.join(d[k]))
PY
timeout 200 .devrun/expanse_cuda_tests > $OUT/call10-cuda-tests.log 2>&1; echo "cuda tests rc $?"; tail -1 $OUT/call10-cuda-tests.log
for tool in memcheck racecheck; do
  timeout 120 /usr/local/cuda/bin/compute-sanitizer --tool $tool --error-exitcode 9 .devrun/expanse_cuda_tests --small > /tmp/san.log 2>&1; echo "$tool rc $?"; tail -1 /tmp/san.log; (echo "=== $tool"; cat /tmp/san.log) >> $OUT/call10-sanitizers.log
done
