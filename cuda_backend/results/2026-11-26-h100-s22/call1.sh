#!/usr/bin/env bash
# Session 22 call 1: the second phase records the stars its odd sites' inboxes hold whole
# (inbox_star_kernel) and walks only the rest, packed from a list. Counted on the CPU (10^6 sites):
# 45% of the odd sites need no search; packed, the phase's lock-step work falls 25% (uniform) and
# 30% (kuzmin). Predicted on the H100 at 4096^2: the second phase 8.2 -> ~6.5 ms on uniform (GPU-only
# 37.7 -> ~36), kuzmin's 19 -> ~14 (68 -> ~63). Against EXPANSE_CUDA_INBOX_FIRST=0 (the old phase),
# two rounds alternated; timelines at 4096^2; CUDA tests, four sanitizers, conformance on CUDA.
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $OUT/call1-inbox-first.jsonl; }
B=.devrun/expanse_bench_cuda
for round in 1 2; do
  for v in 1 0; do
    EXPANSE_CUDA_INBOX_FIRST=$v timeout 150 $B --sizes 4096 --dists uniform,gaussian,grid,kuzmin --reps 5 | tag inbox$v
    EXPANSE_CUDA_INBOX_FIRST=$v timeout 90 $B --sizes 512,2048 --dists uniform,kuzmin --reps 7 | tag inbox$v
  done
done
python3 - $OUT/call1-inbox-first.jsonl <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'], r['side'], r['variant'])].append((g, s.get('stars',0), r.get('deferred'), r.get('triangles')))
for k in sorted(d): print(*k, ' / '.join('%.2f (stars %.2f, def %s, tri %s)'%x for x in d[k]))
PY
for v in 1 0; do for dist in uniform kuzmin; do
  echo "== timeline inbox$v $dist"
  EXPANSE_CUDA_INBOX_FIRST=$v EXPANSE_CUDA_STAR_TIMELINE=1 timeout 60 $B --sizes 4096 --dists $dist --reps 2 2>&1 >/dev/null | tail -12
done; done > $OUT/call1-timeline.txt 2>&1
timeout 120 .devrun/expanse_cuda_tests > $OUT/call1-cuda-tests.log 2>&1; echo "cuda tests rc $?"; tail -1 $OUT/call1-cuda-tests.log
for tool in memcheck racecheck initcheck synccheck; do
  timeout 100 /usr/local/cuda/bin/compute-sanitizer --tool $tool --error-exitcode 9 .devrun/expanse_cuda_tests --small > /tmp/san.log 2>&1; echo "$tool rc $?"; tail -1 /tmp/san.log; (echo "=== $tool"; cat /tmp/san.log) >> $OUT/call1-sanitizers.log
done
timeout 150 .devrun/expanse_conformance --backend cuda > $OUT/call1-conformance.log 2>&1; echo "conformance rc $?"; tail -2 $OUT/call1-conformance.log
