#!/usr/bin/env bash
# Session 26 call 7: the final build (the first phase's retries on the edge stream beside the
# second phase) against session 25's (baseline/, 3508f5f): 4096^2 every input, two rounds
# alternated; 512^2 and 2048^2; timelines; the device preparation's kernels on kuzmin under ncu
# (where its merge's 1.4 ms go); CUDA tests. (The sanitizers and conformance: call 8.)
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT .devrun/baseline/COMMIT
J=$OUT/call7-final.jsonl
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $J; }
B=.devrun/expanse_bench_cuda
for round in 1 2; do
  timeout 150 $B --sizes 4096 --dists uniform,gaussian,grid,kuzmin --reps 5 | tag final
  timeout 150 .devrun/baseline/expanse_bench_cuda --sizes 4096 --dists uniform,gaussian,grid,kuzmin --reps 5 | tag base
done
timeout 100 $B --sizes 512,2048 --dists uniform,gaussian,grid,kuzmin --reps 7 | tag final
timeout 100 .devrun/baseline/expanse_bench_cuda --sizes 512,2048 --dists uniform,gaussian,grid,kuzmin --reps 7 | tag base
python3 - $J <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'], r['side'], r['variant'])].append('%.2f (stars %.2f, sort %.2f, merge %.2f, def %d, seam %.4f%%, h2h %.1f)'%(g,s.get('stars',0),s.get('sort',0),s.get('merge duplicates',0),r['deferred'],100*r.get('seam_share',0),r.get('host_to_host_ms',0)))
for k in sorted(d): print(*k, ' / '.join(d[k]))
PY
for dist in kuzmin gaussian; do
  echo "== timeline $dist"
  EXPANSE_CUDA_STAR_TIMELINE=1 timeout 60 $B --sizes 4096 --dists $dist --reps 2 2>&1 >/dev/null | grep "star stage" | tail -2
done > $OUT/call7-timeline.txt 2>&1
cat $OUT/call7-timeline.txt
timeout 120 /usr/local/cuda/bin/ncu --section SpeedOfLight -k regex:"morton|short|gather|long_run|first_equal|run_|hash|compact|representative|Scan|Radix|Onesweep|Histogram" \
  $B --sizes 4096 --dists kuzmin --reps 1 --no-pipeline > $OUT/call7-ncu-prepare.txt 2>&1; echo "ncu rc $?"
grep -E "^  [a-zA-Z_].*\(|Duration" $OUT/call7-ncu-prepare.txt | sed -n '1,200p' | paste - - | awk '{print}' | cut -c1-150 | tail -40
timeout 200 .devrun/expanse_cuda_tests > $OUT/call7-cuda-tests.log 2>&1; echo "cuda tests rc $?"; tail -1 $OUT/call7-cuda-tests.log
