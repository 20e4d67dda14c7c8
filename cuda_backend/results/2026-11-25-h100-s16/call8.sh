#!/usr/bin/env bash
# Session 16 call 8: the next candidate's point loaded while the current one is judged (the thread
# walker's candidate loop) against 88f976c, alternated, two rounds, GPU-only at 512^2, 1024^2,
# 4096^2, four inputs; both phases under ncu; CUDA tests; conformance on CUDA with two phases.
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $OUT/call8-prefetch.jsonl; }
for round in 1 2; do
  timeout 150 .devrun/baseline/expanse_bench_cuda --sizes 512,1024,4096 --dists uniform,kuzmin,gaussian,grid --reps 5 | tag base-$round
  timeout 150 .devrun/expanse_bench_cuda --sizes 512,1024,4096 --dists uniform,kuzmin,gaussian,grid --reps 5 | tag prefetch-$round
done
python3 - $OUT/call8-prefetch.jsonl <<'PY'
import json,sys
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  print(r['variant'], r['distribution'], r['side'], 'gpu-only %.2f'%g, 'stars %.2f'%s.get('stars',0), 'tri', r['triangles'], 'def', r['deferred'], 'pred', r['predicates'])
PY
for b in baseline/ ""; do
  timeout 200 /usr/local/cuda/bin/ncu --kernel-name regex:"star_kernel" --launch-count 2 --section SpeedOfLight --section InstructionStats --section WarpStateStats --section ComputeWorkloadAnalysis --section MemoryWorkloadAnalysis \
    .devrun/${b}expanse_bench_cuda --sizes 4096 --dists uniform --reps 1 --no-pipeline > $OUT/call8-ncu-${b%/}prefetch.txt 2>&1; echo "ncu $b rc $?"
  grep -E "Duration|Executed Instructions  |Avg. Active Threads|Issue Slots Busy|highest-utilized" $OUT/call8-ncu-${b%/}prefetch.txt
done
timeout 200 .devrun/expanse_cuda_tests > $OUT/call8-cuda-tests.log 2>&1; echo "cuda tests rc $?"; tail -1 $OUT/call8-cuda-tests.log
EXPANSE_CUDA_PHASES=2 timeout 240 .devrun/expanse_conformance --backend cuda > $OUT/call8-conformance-two-phases.log 2>&1; echo "conformance (two phases) rc $?"; tail -2 $OUT/call8-conformance-two-phases.log
