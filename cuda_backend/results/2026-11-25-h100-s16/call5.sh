#!/usr/bin/env bash
# Session 16 call 5: the second phase's sites in the order of the runs their inboxes leave
# (odd_order_kernel, heaviest first) against cell order (EXPANSE_CUDA_ODD_ORDER=0), same build,
# alternated, two rounds, GPU-only; the odd phase under ncu both ways; CUDA tests and
# conformance on CUDA with two phases.
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $OUT/call5-odd-order.jsonl; }
for round in 1 2; do
  EXPANSE_CUDA_ODD_ORDER=0 timeout 150 .devrun/expanse_bench_cuda --sizes 1024,2048,4096 --dists uniform,kuzmin,gaussian,grid --reps 5 | tag cell-$round
  timeout 150 .devrun/expanse_bench_cuda --sizes 1024,2048,4096 --dists uniform,kuzmin,gaussian,grid --reps 5 | tag sorted-$round
done
python3 - $OUT/call5-odd-order.jsonl <<'PY'
import json,sys
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  print(r['variant'], r['distribution'], r['side'], 'gpu-only %.2f'%g, 'stars %.2f'%s.get('stars',0), 'tri', r['triangles'], 'def', r['deferred'])
PY
for v in 0 1; do
  EXPANSE_CUDA_ODD_ORDER=$v timeout 200 /usr/local/cuda/bin/ncu --kernel-name regex:"star_kernel|odd_order|DeviceRadixSort" --launch-count 12 --section SpeedOfLight --section WarpStateStats \
    .devrun/expanse_bench_cuda --sizes 4096 --dists uniform --reps 1 --no-pipeline > $OUT/call5-ncu-order$v.txt 2>&1; echo "ncu $v rc $?"
  grep -E "^  [a-zA-Z_ ]*void|^  [a-z_]+kernel|Duration|Avg. Active Threads" $OUT/call5-ncu-order$v.txt | head -60
done
timeout 200 .devrun/expanse_cuda_tests > $OUT/call5-cuda-tests.log 2>&1; echo "cuda tests rc $?"; tail -2 $OUT/call5-cuda-tests.log
EXPANSE_CUDA_PHASES=2 timeout 240 .devrun/expanse_conformance --backend cuda > $OUT/call5-conformance-two-phases.log 2>&1; echo "conformance (two phases) rc $?"; tail -2 $OUT/call5-conformance-two-phases.log
