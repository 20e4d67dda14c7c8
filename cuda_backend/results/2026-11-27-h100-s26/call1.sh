#!/usr/bin/env bash
# Session 26 call 1: the first phase's retries walked on the edge's stream beside the second
# phase (EXPANSE_CUDA_EARLY_RETRY, default on) against every retry at the end (=0), one build,
# 4096^2 every input, two rounds alternated; 2048^2; timelines; CUDA tests, memcheck, racecheck.
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT
J=$OUT/call1-early-retry.jsonl
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $J; }
B=.devrun/expanse_bench_cuda
for round in 1 2; do
  timeout 150 $B --sizes 4096 --dists uniform,gaussian,grid,kuzmin --reps 5 | tag early
  EXPANSE_CUDA_EARLY_RETRY=0 timeout 150 $B --sizes 4096 --dists uniform,gaussian,grid,kuzmin --reps 5 | tag end
done
timeout 100 $B --sizes 2048 --dists uniform,gaussian,kuzmin --reps 7 | tag early
EXPANSE_CUDA_EARLY_RETRY=0 timeout 100 $B --sizes 2048 --dists uniform,gaussian,kuzmin --reps 7 | tag end
python3 - $J <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'], r['side'], r['variant'])].append('%.2f (stars %.2f, def %d, seam %.4f%%, h2h %.1f)'%(g,s.get('stars',0),r['deferred'],100*r.get('seam_share',0),r.get('host_to_host_ms',0)))
for k in sorted(d): print(*k, ' / '.join(d[k]))
PY
for dist in kuzmin gaussian uniform; do
  for e in 1 0; do
    echo "== timeline $dist early=$e"
    EXPANSE_CUDA_EARLY_RETRY=$e EXPANSE_CUDA_STAR_TIMELINE=1 timeout 60 $B --sizes 4096 --dists $dist --reps 2 2>&1 >/dev/null | grep "star stage" | tail -2
  done
done > $OUT/call1-timeline.txt 2>&1
cat $OUT/call1-timeline.txt
timeout 200 .devrun/expanse_cuda_tests > $OUT/call1-cuda-tests.log 2>&1; echo "cuda tests rc $?"; tail -1 $OUT/call1-cuda-tests.log
for tool in memcheck racecheck; do
  timeout 150 /usr/local/cuda/bin/compute-sanitizer --tool $tool --error-exitcode 9 .devrun/expanse_cuda_tests --small > /tmp/san.log 2>&1; echo "$tool rc $?"; tail -1 /tmp/san.log; (echo "=== $tool"; cat /tmp/san.log) >> $OUT/call1-sanitizers.log
done
