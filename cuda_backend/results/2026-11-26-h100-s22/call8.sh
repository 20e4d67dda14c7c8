#!/usr/bin/env bash
# Session 22 call 8: the recording kernel walks each inbox twice where it holds the star and
# writes the row the second time only: the ~55% of odd sites that must search no longer write a
# partial row that the full walk writes again (~300 MB of partial-sector traffic at 4096^2 of the
# kernel's ~1.5 GB). Expected 1.66 -> ~1.35 ms, GPU-only -0.3 ms. Two rounds against
# EXPANSE_CUDA_INBOX_FIRST=0 at 4096^2 (uniform, gaussian, kuzmin); timelines; CUDA tests, four
# sanitizers, conformance.
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $OUT/call8-inbox-first.jsonl; }
B=.devrun/expanse_bench_cuda
for round in 1 2; do
  for v in 1 0; do
    EXPANSE_CUDA_INBOX_FIRST=$v timeout 150 $B --sizes 4096 --dists uniform,gaussian,kuzmin --reps 5 | tag inbox$v
  done
done
python3 - $OUT/call8-inbox-first.jsonl <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'], r['side'], r['variant'])].append((g, s.get('stars',0), r.get('deferred'), r.get('host_to_host_ms')))
for k in sorted(d): print(*k, ' / '.join('%.2f (stars %.2f, def %s, h2h %.1f)'%x for x in d[k]))
PY
for dist in uniform kuzmin; do
  echo "== timeline $dist"
  EXPANSE_CUDA_STAR_TIMELINE=1 timeout 60 $B --sizes 4096 --dists $dist --reps 2 2>&1 >/dev/null | tail -2
done > $OUT/call8-timeline.txt 2>&1
cat $OUT/call8-timeline.txt
timeout 150 .devrun/expanse_cuda_tests > $OUT/call8-cuda-tests.log 2>&1; echo "cuda tests rc $?"; tail -1 $OUT/call8-cuda-tests.log
for tool in memcheck racecheck initcheck synccheck; do
  timeout 120 /usr/local/cuda/bin/compute-sanitizer --tool $tool --error-exitcode 9 .devrun/expanse_cuda_tests --small > /tmp/san.log 2>&1; echo "$tool rc $?"; tail -1 /tmp/san.log; (echo "=== $tool"; cat /tmp/san.log) >> $OUT/call8-sanitizers.log
done
timeout 150 .devrun/expanse_conformance --backend cuda > $OUT/call8-conformance.log 2>&1; echo "conformance rc $?"; tail -2 $OUT/call8-conformance.log
