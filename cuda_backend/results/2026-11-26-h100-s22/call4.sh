#!/usr/bin/env bash
# Session 22 call 4: the code to keep. Call 3 (H100): GPU-only 4096^2 uniform 37.66 -> 36.97 ms,
# the inbox kernel 1.66 ms (latency-bound, 83% excess sectors; its owned count read the star
# row back: now counted during the walk, expected -0.2 to -0.4 ms). Two rounds alternated against
# EXPANSE_CUDA_INBOX_FIRST=0; the second phase's list walk at 8 and 4 blocks a multiprocessor (its
# work is no longer the old phase's); timelines; CUDA tests, four sanitizers, conformance.
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $OUT/call4-inbox-first.jsonl; }
B=.devrun/expanse_bench_cuda
for round in 1 2; do
  for v in 1 0; do
    EXPANSE_CUDA_INBOX_FIRST=$v timeout 150 $B --sizes 4096 --dists uniform,gaussian,grid,kuzmin --reps 5 | tag inbox$v
    EXPANSE_CUDA_INBOX_FIRST=$v timeout 90 $B --sizes 512,2048 --dists uniform,kuzmin --reps 7 | tag inbox$v
  done
done
for v in 8,8,6 8,4,6; do EXPANSE_CUDA_BLOCKS_PER_SM=$v timeout 60 $B --sizes 4096 --dists uniform --reps 5 | tag blocks$v; done
python3 - $OUT/call4-inbox-first.jsonl <<'PY'
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
done; done > $OUT/call4-timeline.txt 2>&1
timeout 120 .devrun/expanse_cuda_tests > $OUT/call4-cuda-tests.log 2>&1; echo "cuda tests rc $?"; tail -1 $OUT/call4-cuda-tests.log
for tool in memcheck racecheck initcheck synccheck; do
  timeout 100 /usr/local/cuda/bin/compute-sanitizer --tool $tool --error-exitcode 9 .devrun/expanse_cuda_tests --small > /tmp/san.log 2>&1; echo "$tool rc $?"; tail -1 /tmp/san.log; (echo "=== $tool"; cat /tmp/san.log) >> $OUT/call4-sanitizers.log
done
timeout 150 .devrun/expanse_conformance --backend cuda > $OUT/call4-conformance.log 2>&1; echo "conformance rc $?"; tail -2 $OUT/call4-conformance.log
