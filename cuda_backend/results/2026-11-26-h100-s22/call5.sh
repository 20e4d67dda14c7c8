#!/usr/bin/env bash
# Session 22 call 5: the code to keep. Call 4 (H100, two rounds): GPU-only 4096^2 uniform 37.67 ->
# 36.90 ms, kuzmin 69.4 -> 68.2, gaussian 48.1 -> 47.2, but grid 22.25 -> 22.67; the inbox kernel
# still 1.66 ms (273M warp instructions under ncu, ~1,040 a warp, issue-bound at 0.2 a cycle), the
# owned count changing nothing. Now a post found at b gives two steps (u, then a): half the
# look-ups, expected 1.66 -> ~1.1 ms. Two rounds alternated against EXPANSE_CUDA_INBOX_FIRST=0,
# 512^2-4096^2; timelines; CUDA tests, four sanitizers, conformance.
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $OUT/call5-inbox-first.jsonl; }
B=.devrun/expanse_bench_cuda
for round in 1 2; do
  for v in 1 0; do
    EXPANSE_CUDA_INBOX_FIRST=$v timeout 150 $B --sizes 4096 --dists uniform,gaussian,grid,kuzmin --reps 5 | tag inbox$v
    EXPANSE_CUDA_INBOX_FIRST=$v timeout 120 $B --sizes 512,1024,2048 --dists uniform,kuzmin,grid --reps 7 | tag inbox$v
  done
done
python3 - $OUT/call5-inbox-first.jsonl <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'], r['side'], r['variant'])].append((g, s.get('stars',0), s.get('bucket',0), r.get('deferred')))
for k in sorted(d): print(*k, ' / '.join('%.2f (stars %.2f, bucket %.2f, def %s)'%x for x in d[k]))
PY
for v in 1 0; do for dist in uniform kuzmin; do
  echo "== timeline inbox$v $dist"
  EXPANSE_CUDA_INBOX_FIRST=$v EXPANSE_CUDA_STAR_TIMELINE=1 timeout 60 $B --sizes 4096 --dists $dist --reps 2 2>&1 >/dev/null | tail -3
done; done > $OUT/call5-timeline.txt 2>&1
timeout 120 .devrun/expanse_cuda_tests > $OUT/call5-cuda-tests.log 2>&1; echo "cuda tests rc $?"; tail -1 $OUT/call5-cuda-tests.log
for tool in memcheck racecheck initcheck synccheck; do
  timeout 100 /usr/local/cuda/bin/compute-sanitizer --tool $tool --error-exitcode 9 .devrun/expanse_cuda_tests --small > /tmp/san.log 2>&1; echo "$tool rc $?"; tail -1 /tmp/san.log; (echo "=== $tool"; cat /tmp/san.log) >> $OUT/call5-sanitizers.log
done
timeout 150 .devrun/expanse_conformance --backend cuda > $OUT/call5-conformance.log 2>&1; echo "conformance rc $?"; tail -2 $OUT/call5-conformance.log
