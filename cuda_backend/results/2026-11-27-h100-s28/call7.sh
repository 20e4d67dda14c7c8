#!/usr/bin/env bash
# Session 28 call 7: S (the bundle's build): R (call 6) and the sites of a quantile cell in a
# spatial order (where in the cell they lie) for the walks; S with EXPANSE_CUDA_CELL_ORDER=sites
# (= R); against session 27's final build (baseline/, 3e734c0): 4096^2 gaussian and kuzmin two
# rounds alternated, uniform and grid one; 512^2 to 2048^2; kuzmin's lists; S's CUDA tests,
# conformance on CUDA, memcheck on the small cases.
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
B=.devrun/expanse_bench_cuda O=.devrun/baseline/expanse_bench_cuda
for round in 1 2; do
  timeout 120 $B --sizes 4096 --dists gaussian,kuzmin --reps 5 | tag S
  EXPANSE_CUDA_CELL_ORDER=sites timeout 120 $B --sizes 4096 --dists gaussian,kuzmin --reps 5 | tag S-sites
  timeout 120 $O --sizes 4096 --dists gaussian,kuzmin --reps 5 | tag base
done
timeout 120 $B --sizes 4096 --dists uniform,grid --reps 5 | tag S
timeout 120 $O --sizes 4096 --dists uniform,grid --reps 5 | tag base
timeout 120 $B --sizes 512,1024,2048 --dists gaussian,kuzmin --reps 7 | tag S
timeout 120 $O --sizes 512,1024,2048 --dists gaussian,kuzmin --reps 7 | tag base
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
echo "== lists kuzmin S"; EXPANSE_CUDA_STAR_TIMELINE=1 timeout 60 $B --sizes 4096 --dists kuzmin --reps 1 2>&1 >/dev/null | grep "star stage" > $OUT/call7-timeline.txt; cat $OUT/call7-timeline.txt
timeout 150 .devrun/expanse_cuda_tests > $OUT/call7-cuda-tests.log 2>&1; echo "cuda tests rc $?"; grep -E "^FAIL" $OUT/call7-cuda-tests.log | head; tail -1 $OUT/call7-cuda-tests.log
timeout 120 .devrun/expanse_conformance --backend cuda > $OUT/call7-conformance.log 2>&1; echo "conformance rc $?"; tail -2 $OUT/call7-conformance.log
timeout 100 /usr/local/cuda/bin/compute-sanitizer --tool memcheck --error-exitcode 9 .devrun/expanse_cuda_tests --small > $OUT/call7-memcheck.log 2>&1; echo "memcheck rc $?"; tail -1 $OUT/call7-memcheck.log
