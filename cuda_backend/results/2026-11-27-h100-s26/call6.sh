#!/usr/bin/env bash
# Session 26 call 6: three phases of walks (EXPANSE_CUDA_PHASES=3: local id modulo 3; the middle
# phase reads the first's posts and posts to the last's sites) against two, one build, and the
# two-phase default against session 25's build (baseline/, 3508f5f: the inboxes' slots now
# computed for either count); 4096^2 every input, two rounds alternated; 1024^2 and 2048^2;
# timelines; CUDA tests.
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT .devrun/baseline/COMMIT
J=$OUT/call6-phases.jsonl
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $J; }
B=.devrun/expanse_bench_cuda
D="--sizes 4096 --dists uniform,gaussian,grid,kuzmin --reps 5"
for round in 1 2; do
  timeout 150 .devrun/baseline/expanse_bench_cuda $D | tag base
  EXPANSE_CUDA_PHASES=2 timeout 150 $B $D | tag phases2
  EXPANSE_CUDA_PHASES=3 timeout 150 $B $D | tag phases3
done
for p in 2 3; do EXPANSE_CUDA_PHASES=$p timeout 100 $B --sizes 1024,2048 --dists uniform,gaussian,grid,kuzmin --reps 7 | tag phases$p; done
python3 - $J <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'], r['side'], r['variant'])].append('%.2f (stars %.2f, def %d, h2h %.1f)'%(g,s.get('stars',0),r['deferred'],r.get('host_to_host_ms',0)))
for k in sorted(d): print(*k, ' / '.join(d[k]))
PY
for dist in uniform kuzmin gaussian; do
  for p in 2 3; do
    echo "== timeline $dist phases=$p"
    EXPANSE_CUDA_PHASES=$p EXPANSE_CUDA_STAR_TIMELINE=1 timeout 60 $B --sizes 4096 --dists $dist --reps 2 2>&1 >/dev/null | grep "star stage" | tail -2
  done
done > $OUT/call6-timeline.txt 2>&1
cat $OUT/call6-timeline.txt
timeout 240 .devrun/expanse_cuda_tests > $OUT/call6-cuda-tests.log 2>&1; echo "cuda tests rc $?"; tail -3 $OUT/call6-cuda-tests.log
