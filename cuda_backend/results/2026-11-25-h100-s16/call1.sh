#!/usr/bin/env bash
# Session 16 call 1: where the star stage's time goes at real clocks. A timeline (nsys, if the
# machine has it) of 4096^2 uniform and kuzmin with the edge ring's stream beside the phases;
# the even phase under ncu's full set (pipes, issue, warp states); the edge ring on and off.
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
NSYS=$(command -v nsys || ls /usr/local/cuda/bin/nsys /opt/nvidia/nsight-systems/*/bin/nsys /usr/local/cuda/nsight-systems*/bin/nsys 2>/dev/null | head -1)
echo "nsys: ${NSYS:-none}"
if [[ -n $NSYS ]]; then
  for d in uniform kuzmin; do
    timeout 200 $NSYS profile -t cuda -o $OUT/call1-$d --force-overwrite true .devrun/expanse_bench_cuda --sizes 4096 --dists $d --reps 2 --no-pipeline > /dev/null 2>&1; echo "nsys $d rc $?"
    timeout 200 $NSYS stats --report cuda_gpu_trace --format csv --output $OUT/call1-$d $OUT/call1-$d.nsys-rep > /dev/null 2>&1; echo "stats rc $?"
    rm -f $OUT/call1-$d.nsys-rep $OUT/call1-$d.sqlite
    ls $OUT
  done
fi
timeout 300 /usr/local/cuda/bin/ncu --kernel-name regex:"star_kernel" --launch-skip 2 --launch-count 2 --set full \
  .devrun/expanse_bench_cuda --sizes 4096 --dists uniform --reps 1 --no-pipeline > $OUT/call1-ncu-full-uniform.txt 2>&1; echo "ncu rc $?"
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $OUT/call1-edge.jsonl; }
for round in 1 2; do
  timeout 150 .devrun/expanse_bench_cuda --sizes 4096 --dists uniform,kuzmin --reps 5 | tag edge1-$round
  EXPANSE_CUDA_EDGE_DEPTH=0 timeout 150 .devrun/expanse_bench_cuda --sizes 4096 --dists uniform,kuzmin --reps 5 | tag edge0-$round
done
python3 - $OUT/call1-edge.jsonl <<'PY'
import json,sys
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  print(r['variant'], r['distribution'], r['side'], 'gpu-only %.2f'%g, 'stars %.2f'%s.get('stars',0), 'h2h %.1f'%r.get('host_to_host_ms',0))
PY
