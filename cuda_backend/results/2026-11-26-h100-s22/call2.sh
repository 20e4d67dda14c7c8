#!/usr/bin/env bash
# Session 22 call 2: call 1 again with the inbox's posts loaded at once (InboxPosts). Call 1
# (H200): the second phase's list walk took 5.8 ms against the old phase's 8.1 at 4096^2 uniform,
# but inbox_star_kernel took 1.6 ms, a chain of dependent loads a step; expected now ~0.3 ms, the
# phase ~6.1 ms. Call 1 also saw the bucket stage 0.92 -> 2.0 ms on uniform cells with the new
# phase: the search list is now allocated in both variants, to tell the allocation from the kernels.
# Two rounds alternated; timelines at 4096^2; CUDA tests, four sanitizers, conformance on CUDA.
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $OUT/call2-inbox-first.jsonl; }
B=.devrun/expanse_bench_cuda
for round in 1 2; do
  for v in 1 0; do
    EXPANSE_CUDA_INBOX_FIRST=$v timeout 150 $B --sizes 4096 --dists uniform,gaussian,grid,kuzmin --reps 5 | tag inbox$v
    EXPANSE_CUDA_INBOX_FIRST=$v timeout 90 $B --sizes 512,2048 --dists uniform,kuzmin --reps 7 | tag inbox$v
  done
done
python3 - $OUT/call2-inbox-first.jsonl <<'PY'
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
done; done > $OUT/call2-timeline.txt 2>&1
timeout 120 .devrun/expanse_cuda_tests > $OUT/call2-cuda-tests.log 2>&1; echo "cuda tests rc $?"; tail -1 $OUT/call2-cuda-tests.log
for tool in memcheck racecheck initcheck synccheck; do
  timeout 100 /usr/local/cuda/bin/compute-sanitizer --tool $tool --error-exitcode 9 .devrun/expanse_cuda_tests --small > /tmp/san.log 2>&1; echo "$tool rc $?"; tail -1 /tmp/san.log; (echo "=== $tool"; cat /tmp/san.log) >> $OUT/call2-sanitizers.log
done
timeout 150 .devrun/expanse_conformance --backend cuda > $OUT/call2-conformance.log 2>&1; echo "conformance rc $?"; tail -2 $OUT/call2-conformance.log
