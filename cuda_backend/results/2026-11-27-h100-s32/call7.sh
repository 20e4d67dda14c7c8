#!/usr/bin/env bash
# Session 32 call 7: HEAD (the bundle's build: V1 and uniform cells of 2.625 sites) against session
# 31's final code (baseline/, 5c4c1e5) at every size, 4096^2 in two rounds alternated, with
# host-to-host times; uniform 4096^2 with its cells a little finer and coarser still
# (--sites-per-bucket: 1.3125 X sites a cell); the CUDA tests on HEAD.
set -u
bash bench/device/run-on-device.sh env > /dev/null 2>&1; cp $OUT/env.txt $OUT/call7-env.txt 2>/dev/null; rm -f $OUT/env.txt
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT .devrun/baseline/COMMIT
J=$OUT/call7-compare.jsonl
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $J; }
declare -A BIN=([HEAD]=.devrun/expanse_bench_cuda [base]=.devrun/baseline/expanse_bench_cuda)
for round in 1 2; do
  for v in base HEAD; do
    timeout 150 ${BIN[$v]} --sizes 4096 --dists uniform,gaussian,grid,kuzmin --reps 5 | tag $v
  done
done
for v in base HEAD; do
  timeout 150 ${BIN[$v]} --sizes 512,1024,2048 --dists uniform,gaussian,grid,kuzmin --reps 7 | tag $v
done
B=${BIN[HEAD]}
for x in 1.6667 1.8333 2; do timeout 60 $B --sizes 4096 --dists uniform --reps 5 --sites-per-bucket $x | tag "HEAD X $x"; done
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
for v in base HEAD; do
  for dist in uniform kuzmin; do
    echo "== $v $dist"; EXPANSE_CUDA_STAR_TIMELINE=1 timeout 40 ${BIN[$v]} --sizes 4096 --dists $dist --reps 3 2>&1 >/dev/null | grep "star stage timeline" | tail -1
  done
done | tee $OUT/call7-timelines.txt
timeout 150 .devrun/expanse_cuda_tests > $OUT/call7-cuda-tests.log 2>&1; echo "cuda tests rc $?"; grep -E "^FAIL" $OUT/call7-cuda-tests.log | head; tail -1 $OUT/call7-cuda-tests.log
