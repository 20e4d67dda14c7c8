#!/usr/bin/env bash
# Session 27 call 1: a search's end decided without looking its region's cells up (quantile
# axes compare the region with the visited columns' own boundaries) against session 26's final
# build (baseline/, c77244f): 4096^2 gaussian, kuzmin, uniform, two rounds alternated; 2048^2;
# kuzmin's timeline; CUDA tests.
set -u
bash bench/device/run-on-device.sh env > $OUT/call1-env.txt 2>&1
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT .devrun/baseline/COMMIT
J=$OUT/call1-region-end.jsonl
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $J; }
B=.devrun/expanse_bench_cuda
for round in 1 2; do
  timeout 150 $B --sizes 4096 --dists gaussian,kuzmin,uniform --reps 5 | tag new
  timeout 150 .devrun/baseline/expanse_bench_cuda --sizes 4096 --dists gaussian,kuzmin,uniform --reps 5 | tag base
done
timeout 100 $B --sizes 2048 --dists uniform,gaussian,kuzmin --reps 7 | tag new
timeout 100 .devrun/baseline/expanse_bench_cuda --sizes 2048 --dists uniform,gaussian,kuzmin --reps 7 | tag base
python3 - $J <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'], r['side'], r['variant'])].append('%.2f (stars %.2f, def %d, seam %.4f%%)'%(g,s.get('stars',0),r['deferred'],100*r.get('seam_share',0)))
for k in sorted(d): print(*k, ' / '.join(d[k]))
PY
for b in $B .devrun/baseline/expanse_bench_cuda; do
  echo "== timeline kuzmin $b"
  EXPANSE_CUDA_STAR_TIMELINE=1 timeout 60 $b --sizes 4096 --dists kuzmin --reps 2 2>&1 >/dev/null | grep "star stage" | tail -2
done > $OUT/call1-timeline.txt 2>&1
cat $OUT/call1-timeline.txt
timeout 200 .devrun/expanse_cuda_tests > $OUT/call1-cuda-tests.log 2>&1; echo "cuda tests rc $?"; tail -1 $OUT/call1-cuda-tests.log
