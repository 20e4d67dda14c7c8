#!/usr/bin/env bash
# Session 30 call 5: R (the bundle's build): the edge's retry at the main stream's priority, 2
# blocks a multiprocessor, by default; against EXPANSE_CUDA_EDGE_RETRY=edge (as before: the
# edge's stream, 8 blocks) and EXPANSE_CUDA_PHASE0_RETRY=low (the first phase's retry on the
# low stream too); 4096^2 every input, two rounds alternated; 512^2 to 2048^2 one round (R and
# edge); timelines; R's CUDA tests and the conformance suite on CUDA.
set -u
bash bench/device/run-on-device.sh env > /dev/null 2>&1; cp $OUT/env.txt $OUT/call5-env.txt 2>/dev/null; rm -f $OUT/env.txt
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT
J=$OUT/call5-compare.jsonl
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $J; }
B=.devrun/expanse_bench_cuda
for round in 1 2; do
  timeout 150 $B --sizes 4096 --dists uniform,gaussian,grid,kuzmin --reps 5 | tag R
  EXPANSE_CUDA_EDGE_RETRY=edge timeout 150 $B --sizes 4096 --dists uniform,gaussian,grid,kuzmin --reps 5 | tag edge
  EXPANSE_CUDA_PHASE0_RETRY=low timeout 150 $B --sizes 4096 --dists uniform,gaussian,grid,kuzmin --reps 5 | tag p0low
done
timeout 100 $B --sizes 512,1024,2048 --dists uniform,gaussian,grid,kuzmin --reps 7 | tag R
EXPANSE_CUDA_EDGE_RETRY=edge timeout 100 $B --sizes 512,1024,2048 --dists uniform,gaussian,grid,kuzmin --reps 7 | tag edge
python3 - $J <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'], r['side'], r['variant'])].append('%.2f (stars %.2f, def %d, seam %.4f%%, h2h %.1f)'%(g,s.get('stars',0),r['deferred'],100*r.get('seam_share',0),r.get('host_to_host_ms',0)))
for k in sorted(d): print(*k, ' / '.join(d[k]))
PY
for dist in kuzmin uniform; do
  for v in R p0low; do
    echo "== $dist $v"; env $([ $v = p0low ] && echo EXPANSE_CUDA_PHASE0_RETRY=low) EXPANSE_CUDA_STAR_TIMELINE=1 timeout 60 $B --sizes 4096 --dists $dist --reps 2 2>&1 >/dev/null | grep "star stage timeline" | tail -2
  done
done | tee $OUT/call5-timelines.txt
timeout 150 .devrun/expanse_cuda_tests > $OUT/call5-cuda-tests.log 2>&1; echo "cuda tests rc $?"; grep -E "^FAIL" $OUT/call5-cuda-tests.log | head; tail -1 $OUT/call5-cuda-tests.log
timeout 170 .devrun/expanse_conformance --backend cuda > $OUT/call5-conformance.log 2>&1; echo "conformance rc $?"; tail -2 $OUT/call5-conformance.log
