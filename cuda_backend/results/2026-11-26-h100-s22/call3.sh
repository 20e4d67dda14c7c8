#!/usr/bin/env bash
# Session 22 call 3: call 2 (H200) found the inbox kernel still 1.43 ms at 4096^2 uniform (its
# posts now loaded at once), and the bucket stage 0.92 -> 2.0 ms whenever the search list had an
# array of its own. Now: the list in the offsets' room (no new array; bucket expected back at
# ~0.9 ms), one atomic a block of 256 instead of a warp (262k atomics on one word may be the
# 1.4 ms: expected ~0.3 ms). Two rounds alternated against EXPANSE_CUDA_INBOX_FIRST=0; timelines;
# the inbox kernel under ncu (full set, one launch); CUDA tests, four sanitizers, conformance.
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $OUT/call3-inbox-first.jsonl; }
B=.devrun/expanse_bench_cuda
for round in 1 2; do
  for v in 1 0; do
    EXPANSE_CUDA_INBOX_FIRST=$v timeout 150 $B --sizes 4096 --dists uniform,gaussian,grid,kuzmin --reps 5 | tag inbox$v
    EXPANSE_CUDA_INBOX_FIRST=$v timeout 90 $B --sizes 512,2048 --dists uniform,kuzmin --reps 7 | tag inbox$v
  done
done
python3 - $OUT/call3-inbox-first.jsonl <<'PY'
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
done; done > $OUT/call3-timeline.txt 2>&1
timeout 150 /usr/local/cuda/bin/ncu --kernel-name regex:"inbox_star_kernel" --launch-skip 1 --launch-count 1 --set full \
  $B --sizes 4096 --dists uniform --reps 1 --no-pipeline > $OUT/call3-ncu-inbox.txt 2>&1; echo "ncu rc $?"
grep -E "Duration|Memory Throughput|DRAM Throughput|Compute \(SM\)|Achieved Occupancy|Registers Per|L2 Hit|Warp Cycles Per Issued|One or More Eligible" $OUT/call3-ncu-inbox.txt | head -20
timeout 120 .devrun/expanse_cuda_tests > $OUT/call3-cuda-tests.log 2>&1; echo "cuda tests rc $?"; tail -1 $OUT/call3-cuda-tests.log
for tool in memcheck racecheck initcheck synccheck; do
  timeout 100 /usr/local/cuda/bin/compute-sanitizer --tool $tool --error-exitcode 9 .devrun/expanse_cuda_tests --small > /tmp/san.log 2>&1; echo "$tool rc $?"; tail -1 /tmp/san.log; (echo "=== $tool"; cat /tmp/san.log) >> $OUT/call3-sanitizers.log
done
timeout 150 .devrun/expanse_conformance --backend cuda > $OUT/call3-conformance.log 2>&1; echo "conformance rc $?"; tail -2 $OUT/call3-conformance.log
