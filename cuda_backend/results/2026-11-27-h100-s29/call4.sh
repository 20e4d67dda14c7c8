#!/usr/bin/env bash
# Session 29 call 4: F (the bundle's build, 059860b): call 3's E1 for every input but lattices,
# whose walks keep their former code; against session 28's final build (baseline/): 4096^2 every
# input, two rounds alternated; 512^2 to 2048^2 one round; kuzmin's timeline; F's CUDA tests and
# the conformance suite on CUDA.
set -u
bash bench/device/run-on-device.sh env > /dev/null 2>&1; cp $OUT/env.txt $OUT/call4-env.txt 2>/dev/null; rm -f $OUT/env.txt
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT .devrun/baseline/COMMIT
J=$OUT/call4-compare.jsonl
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $J; }
B=.devrun/expanse_bench_cuda O=.devrun/baseline/expanse_bench_cuda
for round in 1 2; do
  timeout 150 $B --sizes 4096 --dists uniform,gaussian,grid,kuzmin --reps 5 | tag F
  timeout 150 $O --sizes 4096 --dists uniform,gaussian,grid,kuzmin --reps 5 | tag base
done
timeout 100 $B --sizes 512,1024,2048 --dists uniform,gaussian,grid,kuzmin --reps 7 | tag F
timeout 100 $O --sizes 512,1024,2048 --dists uniform,gaussian,grid,kuzmin --reps 7 | tag base
python3 - $J <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'], r['side'], r['variant'])].append('%.2f (stars %.2f unpiped %.2f, def %d, seam %.4f%%, h2h %.1f)'%(g,s.get('stars',0),r['device_stages_ms'].get('stars',0),r['deferred'],100*r.get('seam_share',0),r.get('host_to_host_ms',0)))
for k in sorted(d): print(*k, ' / '.join(d[k]))
PY
echo "== kuzmin F"; EXPANSE_CUDA_STAR_TIMELINE=1 timeout 60 $B --sizes 4096 --dists kuzmin --reps 1 2>&1 >/dev/null | grep "star stage" | tail -2 | tee $OUT/call4-timeline.txt
timeout 150 .devrun/expanse_cuda_tests > $OUT/call4-cuda-tests.log 2>&1; echo "cuda tests rc $?"; grep -E "^FAIL" $OUT/call4-cuda-tests.log | head; tail -1 $OUT/call4-cuda-tests.log
timeout 170 .devrun/expanse_conformance --backend cuda > $OUT/call4-conformance.log 2>&1; echo "conformance rc $?"; tail -2 $OUT/call4-conformance.log
