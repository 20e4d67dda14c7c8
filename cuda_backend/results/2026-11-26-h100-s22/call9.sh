#!/usr/bin/env bash
# Session 22 call 9: with the recording kernel at 1.0 ms (call 8, against 1.66), do the inputs
# that kept one kernel now gain too? Call 5 had uniform 2048^2 +0.25 ms and the 4096^2 lattice
# +0.43 with the new phase; expected now about even. Two rounds, forced on and off.
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $OUT/call9-small-and-lattice.jsonl; }
B=.devrun/expanse_bench_cuda
for round in 1 2; do
  for v in 1 0; do
    EXPANSE_CUDA_INBOX_FIRST=$v timeout 100 $B --sizes 1024,2048 --dists uniform,grid --reps 7 | tag inbox$v
    EXPANSE_CUDA_INBOX_FIRST=$v timeout 100 $B --sizes 4096 --dists grid --reps 5 | tag inbox$v
  done
done
python3 - $OUT/call9-small-and-lattice.jsonl <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'], r['side'], r['variant'])].append((g, s.get('stars',0)))
for k in sorted(d): print(*k, ' / '.join('%.2f (stars %.2f)'%x for x in d[k]))
PY
