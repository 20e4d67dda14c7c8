#!/usr/bin/env bash
# Session 33 call 2: phases generalised (StarInbox: site i walks in phase i % P, posts to later
# phases' sites; HEAD) against session 32's final code (baseline/, ffeff5d): P = 2 (the default,
# as before), 3 and 4 (EXPANSE_CUDA_PHASES), 4096^2 in two rounds alternated, then 512^2 to
# 2048^2; timelines; the CUDA tests with 2, 3 and 4 phases (the variable applies at every size).
set -u
bash bench/device/run-on-device.sh env > /dev/null 2>&1; cp $OUT/env.txt $OUT/call2-env.txt 2>/dev/null; rm -f $OUT/env.txt
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT .devrun/baseline/COMMIT
J=$OUT/call2-compare.jsonl
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $J; }
B=.devrun/expanse_bench_cuda
for round in 1 2; do
  timeout 150 .devrun/baseline/expanse_bench_cuda --sizes 4096 --dists uniform,gaussian,grid,kuzmin --reps 5 | tag base
  for p in 2 3 4; do EXPANSE_CUDA_PHASES=$p timeout 150 $B --sizes 4096 --dists uniform,gaussian,grid,kuzmin --reps 5 | tag "P$p"; done
done
timeout 100 .devrun/baseline/expanse_bench_cuda --sizes 512,1024,2048 --dists uniform,gaussian,grid,kuzmin --reps 7 | tag base
for p in 2 3; do EXPANSE_CUDA_PHASES=$p timeout 100 $B --sizes 512,1024,2048 --dists uniform,gaussian,grid,kuzmin --reps 7 | tag "P$p"; done
python3 - $J <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'], r['side'], r['variant'])].append('%.2f (stars %.2f, def %d, seam %.5f%%, h2h %.1f)'%(g,s.get('stars',0),r['deferred'],100*r.get('seam_share',0),r.get('host_to_host_ms',0)))
for k in sorted(d): print(*k, ' / '.join(d[k]))
PY
for p in 2 3 4; do
  for dist in uniform kuzmin; do
    echo "== P$p $dist"; EXPANSE_CUDA_PHASES=$p EXPANSE_CUDA_STAR_TIMELINE=1 timeout 40 $B --sizes 4096 --dists $dist --reps 3 2>&1 >/dev/null | grep "star stage timeline" | tail -1
  done
done | tee $OUT/call2-timelines.txt
for p in 2 3 4; do
  EXPANSE_CUDA_PHASES=$p timeout 150 .devrun/expanse_cuda_tests > $OUT/call2-cuda-tests-P$p.log 2>&1; echo "P$p cuda tests rc $?"; grep -E "^FAIL|FAILED" $OUT/call2-cuda-tests-P$p.log | head -5; tail -1 $OUT/call2-cuda-tests-P$p.log
done
