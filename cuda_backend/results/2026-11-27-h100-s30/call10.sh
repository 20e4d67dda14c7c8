#!/usr/bin/env bash
# Session 30 call 10: the edge's first pass in two tiers (EXPANSE_CUDA_EDGE_PACK=B: first with
# budget B, then the sites past it walked together, packed into few blocks, with the first pass's
# budget), so that the long walks hold few blocks beside the first phase; B = 128, 256, 512
# against none; one build (the bundle's), 4096^2 uniform, gaussian and kuzmin, two rounds
# alternated; uniform's timelines; the CUDA tests with B = 64.
set -u
python3 -c "import tarfile; tarfile.open('.devrun/bundle.tar.xz').extractall('.devrun')"
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT; nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
J=$OUT/call10-compare.jsonl
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $J; }
B=.devrun/expanse_bench_cuda
for round in 1 2; do
  for v in 0 128 256 512; do
    EXPANSE_CUDA_EDGE_PACK=$v timeout 150 $B --sizes 4096 --dists uniform,gaussian,kuzmin --reps 5 | tag pack-$v
  done
done
python3 - $J <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'], r['variant'])].append('%.2f (stars %.2f, def %d)'%(g,s.get('stars',0),r['deferred']))
for k in sorted(d): print(*k, ' / '.join(d[k]))
PY
for v in 0 256; do
  for dist in uniform gaussian; do
    echo "== $dist pack $v"; EXPANSE_CUDA_EDGE_PACK=$v EXPANSE_CUDA_STAR_TIMELINE=1 timeout 60 $B --sizes 4096 --dists $dist --reps 2 2>&1 >/dev/null | grep "star stage" | tail -2
  done
done | tee $OUT/call10-timelines.txt
EXPANSE_CUDA_EDGE_PACK=64 timeout 150 .devrun/expanse_cuda_tests > $OUT/call10-cuda-tests.log 2>&1; echo "cuda tests (pack 64) rc $?"; grep -E "^FAIL" $OUT/call10-cuda-tests.log | head; tail -1 $OUT/call10-cuda-tests.log
