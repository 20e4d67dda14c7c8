#!/usr/bin/env bash
# Session 18 call 4: the phases' blocks launched in another order (EXPANSE_CUDA_BLOCK_ORDER: 0 as
# now, 1 reversed, 2 both ends of the cell order first). Under ncu (call 2) kuzmin's first phase
# kept its multiprocessors active 93% of its cycles against uniform's 99.7%: a tail, and the cell
# order's last blocks (the top rows: the far tail in y) are its heaviest (counted on the CPU).
# 2048^2 and 4096^2, kuzmin, gaussian, uniform; two rounds alternated, the timeline on round 2.
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $OUT/call4-order.jsonl; }
B=".devrun/expanse_bench_cuda --sizes 2048,4096 --dists kuzmin,gaussian,uniform --reps 5"
for o in 0 1 2; do EXPANSE_CUDA_BLOCK_ORDER=$o timeout 60 $B | tag o$o-1; done
for o in 0 1 2; do
  EXPANSE_CUDA_BLOCK_ORDER=$o EXPANSE_CUDA_STAR_TIMELINE=1 timeout 60 $B 2> /tmp/t.txt | tag o$o-2
  (echo "=== order $o round 2"; grep timeline /tmp/t.txt) >> $OUT/call4-timeline.txt
done
python3 - $OUT/call4-order.jsonl <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'],r['side'],r['variant'].split('-')[0])].append('%.2f (stars %.2f) def %d'%(g,s.get('stars',0),r['deferred']))
for k in sorted(d): print(k, ' | '.join(d[k]))
PY
EXPANSE_CUDA_BLOCK_ORDER=2 timeout 60 .devrun/expanse_cuda_tests > $OUT/call4-cuda-tests.log 2>&1; echo "cuda tests (order 2) rc $?"; tail -1 $OUT/call4-cuda-tests.log
