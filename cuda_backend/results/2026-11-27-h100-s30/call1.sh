#!/usr/bin/env bash
# Session 30 call 1: S (the bundle's build): a retrying warp passes stretches of empty rows by
# unclipped loads (skip_empty_rows), against session 29's final code (baseline/, e15dfa3 built at
# a87fdb5): 4096^2 every input, two rounds alternated; kuzmin's and gaussian's star stage
# timelines; S's CUDA tests and the conformance suite on CUDA.
set -u
bash bench/device/run-on-device.sh env > /dev/null 2>&1; cp $OUT/env.txt $OUT/call1-env.txt 2>/dev/null; rm -f $OUT/env.txt
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT .devrun/baseline/COMMIT
J=$OUT/call1-compare.jsonl
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $J; }
B=.devrun/expanse_bench_cuda O=.devrun/baseline/expanse_bench_cuda
for round in 1 2; do
  timeout 150 $B --sizes 4096 --dists uniform,gaussian,grid,kuzmin --reps 5 | tag S
  timeout 150 $O --sizes 4096 --dists uniform,gaussian,grid,kuzmin --reps 5 | tag base
done
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
for dist in kuzmin gaussian; do
  for b in S:$B base:$O; do
    echo "== $dist ${b%%:*}"; EXPANSE_CUDA_STAR_TIMELINE=1 timeout 60 ${b#*:} --sizes 4096 --dists $dist --reps 3 2>&1 >/dev/null | grep "star stage" | tail -4
  done
done | tee $OUT/call1-timelines.txt
timeout 150 .devrun/expanse_cuda_tests > $OUT/call1-cuda-tests.log 2>&1; echo "cuda tests rc $?"; grep -E "^FAIL" $OUT/call1-cuda-tests.log | head; tail -1 $OUT/call1-cuda-tests.log
timeout 170 .devrun/expanse_conformance --backend cuda > $OUT/call1-conformance.log 2>&1; echo "conformance rc $?"; tail -2 $OUT/call1-conformance.log
