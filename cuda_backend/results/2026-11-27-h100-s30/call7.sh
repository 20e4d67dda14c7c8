#!/usr/bin/env bash
# Session 30 call 7: F (the bundle's build) against the baseline (e15dfa3's code) on the 512^2
# lattice alone and in call 6's order (every input at 512^2, then 1024^2), three rounds
# alternated, after call 6 measured it 0.80 -> 0.99 ms in every stage; racecheck on F's small
# cases again with a longer limit (call 6's 60 s ran out).
set -u
python3 -c "import tarfile; tarfile.open('.devrun/bundle.tar.xz').extractall('.devrun')"
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT .devrun/baseline/COMMIT; nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
J=$OUT/call7-grid512.jsonl
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $J; }
B=.devrun/expanse_bench_cuda O=.devrun/baseline/expanse_bench_cuda
for round in 1 2 3; do
  timeout 60 $B --sizes 512 --dists grid --reps 15 | tag F-alone
  timeout 60 $O --sizes 512 --dists grid --reps 15 | tag base-alone
  timeout 90 $B --sizes 512,1024 --dists uniform,gaussian,grid,kuzmin --reps 7 | tag F-order
  timeout 90 $O --sizes 512,1024 --dists uniform,gaussian,grid,kuzmin --reps 7 | tag base-order
done
python3 - $J <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'], r['side'], r['variant'])].append('%.2f (stars %.2f sort %.3f)'%(g,s.get('stars',0),s.get('sort',0)))
for k in sorted(d): print(*k, ' / '.join(d[k]))
PY
timeout 400 /usr/local/cuda/bin/compute-sanitizer --tool racecheck --error-exitcode 9 .devrun/expanse_cuda_tests --small > $OUT/call7-racecheck.log 2>&1; echo "racecheck rc $?"; tail -1 $OUT/call7-racecheck.log
