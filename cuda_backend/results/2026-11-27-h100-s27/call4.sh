#!/usr/bin/env bash
# Session 27 call 4: E (the bundle's build): D and the nearest neighbour searched before the
# walk's loops by squared distance alone; D (variantD/, 1ab934b): a walk of its own for each kind
# of grid (uniform cells, quantile cells with both guides, any other), no guided copy for
# lattices; against session 26's final build (baseline/, c77244f): 4096^2 every input, two rounds
# alternated; 512^2 to 2048^2; timelines; E's CUDA tests (the sanitizers and conformance: call 5).
set -u
bash bench/device/run-on-device.sh env > $OUT/call4-env.txt 2>&1
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT .devrun/variantD/COMMIT .devrun/baseline/COMMIT
J=$OUT/call4-final.jsonl
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $J; }
B=.devrun/expanse_bench_cuda D=.devrun/variantD/expanse_bench_cuda O=.devrun/baseline/expanse_bench_cuda
for round in 1 2; do
  timeout 150 $B --sizes 4096 --dists uniform,gaussian,grid,kuzmin --reps 5 | tag E
  timeout 150 $D --sizes 4096 --dists uniform,gaussian,grid,kuzmin --reps 5 | tag D
  timeout 150 $O --sizes 4096 --dists uniform,gaussian,grid,kuzmin --reps 5 | tag base
done
timeout 120 $B --sizes 512,1024,2048 --dists uniform,gaussian,grid,kuzmin --reps 7 | tag E
timeout 120 $D --sizes 512,1024,2048 --dists uniform,gaussian,grid,kuzmin --reps 7 | tag D
timeout 120 $O --sizes 512,1024,2048 --dists uniform,gaussian,grid,kuzmin --reps 7 | tag base
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
for dist in uniform kuzmin; do for b in E:$B D:$D; do
  echo "== timeline $dist ${b%%:*}"
  EXPANSE_CUDA_STAR_TIMELINE=1 timeout 60 ${b#*:} --sizes 4096 --dists $dist --reps 2 2>&1 >/dev/null | grep "star stage" | tail -2
done; done > $OUT/call4-timeline.txt 2>&1
cat $OUT/call4-timeline.txt
timeout 200 .devrun/expanse_cuda_tests > $OUT/call4-cuda-tests.log 2>&1; echo "cuda tests rc $?"; tail -1 $OUT/call4-cuda-tests.log
