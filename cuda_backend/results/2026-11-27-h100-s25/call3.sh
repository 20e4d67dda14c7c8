#!/usr/bin/env bash
# Session 25 call 3: the bucketing's read-backs (the evenness test's word, the guides' keys)
# written by their kernels into the pinned words (mapped memory) instead of copied, against
# cb7ffda (baseline/, call 2's build). Call 2 had the pipelined bucket stage 1.1 ms longer than
# the unpipelined one on quantile cells (kuzmin 2.67 against 1.51, gaussian 2.62 against 1.47;
# uniform cells 1.08 against 1.00): the copies queue behind the side stream's copies of the
# sites to the host, which run beside the growth. Expected: those stages at ~1.5 ms, kuzmin and
# gaussian GPU-only -1.1 ms, uniform -0.05.
# Also an experiment: EXPANSE_CUDA_POOL_RESERVE_MB (the pool maps 20 GB at once): call 2's
# pipelined kuzmin stars ran 1.5-2 ms longer than unpipelined (52.5 against 50.8-51.0), uniform
# and gaussian not; if the pool's placement is why, one mapping may even it out.
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT .devrun/baseline/COMMIT
J=$OUT/call3-readbacks.jsonl
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $J; }
B=.devrun/expanse_bench_cuda
for round in 1 2; do
  timeout 150 $B --sizes 4096 --dists uniform,gaussian,kuzmin --reps 5 | tag mapped
  timeout 150 .devrun/baseline/expanse_bench_cuda --sizes 4096 --dists uniform,gaussian,kuzmin --reps 5 | tag base
done
EXPANSE_CUDA_POOL_RESERVE_MB=20000 timeout 150 $B --sizes 4096 --dists uniform,kuzmin --reps 5 | tag reserve
timeout 100 $B --sizes 512,2048 --dists uniform,kuzmin --reps 7 | tag mapped
timeout 100 .devrun/baseline/expanse_bench_cuda --sizes 512,2048 --dists uniform,kuzmin --reps 7 | tag base
python3 - $J <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  u=r.get('device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'], r['side'], r['variant'])].append('%.2f (stars %.2f/%.2f unpiped, bucket %.2f/%.2f, def %d, h2h %.1f)'%(g,s.get('stars',0),u.get('stars',0),s.get('bucket',0),u.get('bucket',0),r['deferred'],r.get('host_to_host_ms',0)))
for k in sorted(d): print(*k, ' / '.join(d[k]))
PY
timeout 200 .devrun/expanse_cuda_tests > $OUT/call3-cuda-tests.log 2>&1; echo "cuda tests rc $?"; tail -1 $OUT/call3-cuda-tests.log
for tool in memcheck racecheck initcheck synccheck; do
  timeout 150 /usr/local/cuda/bin/compute-sanitizer --tool $tool --error-exitcode 9 .devrun/expanse_cuda_tests --small > /tmp/san.log 2>&1; echo "$tool rc $?"; tail -1 /tmp/san.log; (echo "=== $tool"; cat /tmp/san.log) >> $OUT/call3-sanitizers.log
done
timeout 150 .devrun/expanse_conformance --backend cuda > $OUT/call3-conformance.log 2>&1; echo "conformance rc $?"; tail -2 $OUT/call3-conformance.log
