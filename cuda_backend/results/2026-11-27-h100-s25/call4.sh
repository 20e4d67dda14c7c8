#!/usr/bin/env bash
# Session 25 call 4: the final build (the pool-reserve switch of call 3 removed: no effect).
# Figs. IV.2 / IV.3's GPU records at this commit (expanse-bench scaling, CUDA and Vulkan, our
# layout, 32^2..4096^2, uniform and gaussian), then expanse_bench_cuda at 4096^2 (four inputs, two
# rounds) and 512^2 / 2048^2, the CUDA tests and the conformance suite on CUDA.
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
commit=$(cat .devrun/COMMIT); echo $commit
mkdir -p $OUT/results
EXPANSE_COMMIT=$commit timeout 220 .devrun/expanse-bench --experiment scaling --backends cuda,vulkan --dist uniform,gaussian \
  -n 32^2,64^2,128^2,256^2,512^2,1024^2,2048^2,4096^2 --layouts default -r 5 --max-seconds 8 \
  --note "device run" --warmup 1 -o $OUT/results/scaling.jsonl > $OUT/call4-scaling.log 2>&1; echo "scaling rc $?"
J=$OUT/call4-final.jsonl
B=.devrun/expanse_bench_cuda
for round in 1 2; do timeout 150 $B --sizes 4096 --dists uniform,gaussian,grid,kuzmin --reps 5 >> $J; done
timeout 100 $B --sizes 512,2048 --dists uniform,gaussian,grid,kuzmin --reps 7 >> $J
python3 - $J <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  try: r=json.loads(l)
  except Exception: continue
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'], r['side'])].append('%.2f (stars %.2f, bucket %.2f, def %d, seam %.4f%%, h2h %.1f)'%(g,s.get('stars',0),s.get('bucket',0),r['deferred'],100*r.get('seam_share',0),r.get('host_to_host_ms',0)))
for k in sorted(d): print(*k, ' / '.join(d[k]))
PY
timeout 200 .devrun/expanse_cuda_tests > $OUT/call4-cuda-tests.log 2>&1; echo "cuda tests rc $?"; tail -1 $OUT/call4-cuda-tests.log
timeout 150 .devrun/expanse_conformance --backend cuda > $OUT/call4-conformance.log 2>&1; echo "conformance rc $?"; tail -2 $OUT/call4-conformance.log
