#!/usr/bin/env bash
# Session 19 call 2: call 1 found a smaller first box slower at 4096^2 (uniform stars 32.5 ->
# 36.1 ms with 7% fewer predicates) though faster at 512^2: so larger first boxes, 4096^2
# uniform and kuzmin, 2048^2 uniform; two rounds alternated.
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $OUT/call2-larger.jsonl; }
B=".devrun/expanse_bench_cuda --sizes 2048,4096 --dists uniform,kuzmin --reps 5"
for round in 1 2; do
  for fb in 1,1 1.25,1 1.5,1 1,1.5 1.25,1.25 1.5,1.5 2,1; do EXPANSE_CUDA_FIRST_BOX=$fb timeout 60 $B | tag fb$fb-$round; done
done
python3 - $OUT/call2-larger.jsonl <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'],r['side'],r['variant'].rsplit('-',1)[0])].append('%.2f (stars %.2f) pred %.1f def %d'%(g,s.get('stars',0),r['predicates']/r['n'],r['deferred']))
for k in sorted(d): print(k, ' | '.join(d[k]))
PY
