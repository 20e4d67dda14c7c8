#!/usr/bin/env bash
# Session 27 call 6: Figs. IV.2 / IV.3's GPU records at the final build (expanse-bench scaling,
# CUDA and Vulkan, our layout, 32^2..4096^2, uniform and gaussian; as run-on-device.sh's
# `figures`, its first step).
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
commit=$(cat .devrun/COMMIT); echo $commit
mkdir -p $OUT/results
EXPANSE_COMMIT=$commit timeout 400 .devrun/expanse-bench --experiment scaling --backends cuda,vulkan --dist uniform,gaussian \
  -n 32^2,64^2,128^2,256^2,512^2,1024^2,2048^2,4096^2 --layouts default -r 5 --max-seconds 8 \
  --note "device run" --warmup 1 -o $OUT/results/scaling.jsonl > $OUT/call6-scaling.log 2>&1; echo "scaling rc $?"
tail -5 $OUT/call6-scaling.log
python3 - $OUT/results/scaling.jsonl <<'PY'
import json,sys
for l in open(sys.argv[1]):
  r=json.loads(l)
  if r.get('skipped'): print(r['backend'], r.get('n'), 'skipped', r.get('reason')); continue
  print(r['backend'], r['distribution'], r['n'], '%.2f'%r['time_ms']['total']['median'])
PY
