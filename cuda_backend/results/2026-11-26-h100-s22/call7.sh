#!/usr/bin/env bash
# Session 22 call 7: host to host again. Call 6's machine (a fresh one) moved uniform's first
# 4096^2 run slowly over the bus (upload 31.5 ms, download 70.5, against ~20 and ~28): 211.6 ms.
# Nothing this session changed on the host's path; three rounds of 4096^2 uniform and kuzmin.
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT
B=.devrun/expanse_bench_cuda
for round in 1 2 3; do timeout 100 $B --sizes 4096 --dists uniform,kuzmin --reps 5 >> $OUT/call7-h2h.jsonl; done
python3 - $OUT/call7-h2h.jsonl <<'PY'
import json,sys
for l in open(sys.argv[1]):
  try: r=json.loads(l)
  except Exception: continue
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  print(r['distribution'], r['side'], 'h2h %.1f GPU-only %.2f upload %.1f download %.1f'%(r.get('host_to_host_ms',0), g, s.get('upload',0), s.get('download',0)))
PY
