#!/usr/bin/env bash
# Session 29 call 10: call 9's timelines had the whole gain in the second phase, the first a
# little slower. H (the bundle's build): G with the boxes' boundary test in the second phase's
# walks only (ReadsInbox); against G (g/) and session 28's final code (baseline/): kuzmin,
# gaussian and uniform 4096^2, two rounds alternated; kuzmin's and gaussian's timelines, H.
set -u
python3 -c "import tarfile; tarfile.open('.devrun/bundle.tar.xz').extractall('.devrun')"
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT .devrun/g/COMMIT .devrun/baseline/COMMIT; nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
J=$OUT/call10-compare.jsonl
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $J; }
B=.devrun/expanse_bench_cuda G=.devrun/g/expanse_bench_cuda O=.devrun/baseline/expanse_bench_cuda
for round in 1 2; do
  for b in H:$B G:$G base:$O; do timeout 100 ${b#*:} --sizes 4096 --dists uniform,gaussian,kuzmin --reps 5 | tag ${b%%:*}; done
done
python3 - $J <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'], r['side'], r['variant'])].append('%.2f (stars %.2f unpiped %.2f, def %d)'%(g,s.get('stars',0),r['device_stages_ms'].get('stars',0),r['deferred']))
for k in sorted(d): print(*k, ' / '.join(d[k]))
PY
for dist in kuzmin gaussian; do
  echo "== $dist H"; EXPANSE_CUDA_STAR_TIMELINE=1 timeout 60 $B --sizes 4096 --dists $dist --reps 3 2>&1 >/dev/null | grep "star stage timeline" | tail -3
done | tee $OUT/call10-timelines.txt
