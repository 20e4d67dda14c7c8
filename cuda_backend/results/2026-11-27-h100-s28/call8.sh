#!/usr/bin/env bash
# Session 28 call 8: X (the bundle's build): R (call 6) and, where the device's preparation left
# long runs of equal codes in input order, a cell's sites walked in x order; against session
# 27's final build (baseline/, 3e734c0): 4096^2 kuzmin and gaussian, two rounds alternated, uniform
# one; kuzmin's lists; X's CUDA tests and conformance on CUDA.
set -u
bash bench/device/run-on-device.sh env > /dev/null 2>&1; cp $OUT/env.txt $OUT/call8-env.txt 2>/dev/null; rm -f $OUT/env.txt
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT .devrun/baseline/COMMIT
J=$OUT/call8-compare.jsonl
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $J; }
B=.devrun/expanse_bench_cuda O=.devrun/baseline/expanse_bench_cuda
for round in 1 2; do
  timeout 100 $B --sizes 4096 --dists kuzmin,gaussian --reps 5 | tag X
  timeout 100 $O --sizes 4096 --dists kuzmin,gaussian --reps 5 | tag base
done
timeout 60 $B --sizes 4096 --dists uniform --reps 5 | tag X
python3 - $J <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'], r['side'], r['variant'])].append('%.2f (sort %.2f merge %.2f bucket %.2f stars %.2f unpiped %.2f, def %d, seam %.4f%%, h2h %.1f)'%(g,s.get('sort',0),s.get('merge duplicates',0),s.get('bucket',0),s.get('stars',0),r['device_stages_ms'].get('stars',0),r['deferred'],100*r.get('seam_share',0),r.get('host_to_host_ms',0)))
for k in sorted(d): print(*k, ' / '.join(d[k]))
PY
echo "== lists kuzmin X"; EXPANSE_CUDA_STAR_TIMELINE=1 timeout 60 $B --sizes 4096 --dists kuzmin --reps 1 2>&1 >/dev/null | grep "star stage" > $OUT/call8-timeline.txt; grep lists $OUT/call8-timeline.txt
timeout 120 .devrun/expanse_cuda_tests > $OUT/call8-cuda-tests.log 2>&1; echo "cuda tests rc $?"; grep -E "^FAIL" $OUT/call8-cuda-tests.log | head; tail -1 $OUT/call8-cuda-tests.log
timeout 100 .devrun/expanse_conformance --backend cuda > $OUT/call8-conformance.log 2>&1; echo "conformance rc $?"; tail -2 $OUT/call8-conformance.log
