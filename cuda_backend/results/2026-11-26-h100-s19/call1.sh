#!/usr/bin/env bash
# Session 19 call 1: the apex searches' first box (EXPANSE_CUDA_FIRST_BOX=reach,offset; 1,1 is
# star.comp's box, the default) and the neighbours' emit taking a neighbour's index from a star
# already at hand where its site owns it (default) against searching the owner's star
# (EXPANSE_CUDA_EMIT=search). Counted on the CPU at 1M uniform sites: 0.75,0.5 -> predicates
# 77.1 -> 69.2 a site, lock-step work -4%; gaussian -4%; kuzmin +8% lock-step work.
# Two rounds alternated; CUDA tests and memcheck on the new default emit.
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $OUT/call1-compare.jsonl; }
BU=".devrun/expanse_bench_cuda --sizes 512,4096 --dists uniform --reps 5"
BQ=".devrun/expanse_bench_cuda --sizes 4096 --dists kuzmin,gaussian,grid --reps 5"
for round in 1 2; do
  for fb in 1,1 0.75,0.5 0.6,0.5 0.75,0.75; do EXPANSE_CUDA_FIRST_BOX=$fb timeout 60 $BU | tag fb$fb-$round; done
  for fb in 1,1 0.75,0.5; do EXPANSE_CUDA_FIRST_BOX=$fb timeout 90 $BQ | tag fb$fb-$round; done
  EXPANSE_CUDA_EMIT=search timeout 60 .devrun/expanse_bench_cuda --sizes 4096 --dists uniform,kuzmin --reps 5 | tag emitsearch-$round
done
python3 - $OUT/call1-compare.jsonl <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'],r['side'],r['variant'].rsplit('-',1)[0])].append('%.2f (stars %.2f emit %.2f) pred %.1f def %d tri %d'%(g,s.get('stars',0),s.get('emit',0),r['predicates']/r['n'],r['deferred'],r['triangles']))
for k in sorted(d): print(k, ' | '.join(d[k]))
PY
timeout 60 .devrun/expanse_cuda_tests > $OUT/call1-cuda-tests.log 2>&1; echo "cuda tests rc $?"; tail -1 $OUT/call1-cuda-tests.log
EXPANSE_CUDA_FIRST_BOX=0.75,0.5 timeout 60 .devrun/expanse_cuda_tests > /tmp/t2.log 2>&1; echo "cuda tests (first box 0.75,0.5) rc $?"; tail -1 /tmp/t2.log
timeout 60 /usr/local/cuda/bin/compute-sanitizer --tool memcheck --error-exitcode 9 .devrun/expanse_cuda_tests --small > $OUT/call1-memcheck.log 2>&1; echo "memcheck rc $?"; tail -1 $OUT/call1-memcheck.log
