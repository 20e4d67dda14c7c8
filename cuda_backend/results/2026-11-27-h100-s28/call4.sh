#!/usr/bin/env bash
# Session 28 call 4: kuzmin's pipelined second phase 1.5 ms slower (call 3): with the sites'
# copy to the host before the growth (EXPANSE_CUDA_SITES_COPY=before) instead of beside it.
set -u
python3 -c "import tarfile; tarfile.open('.devrun/bundle.tar.xz').extractall('.devrun')"
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
export LD_LIBRARY_PATH=$PWD/.devrun/lib
B=.devrun/expanse_bench_cuda
for copy in before alongside before alongside; do
  echo "== kuzmin, sites copied $copy"
  if [[ $copy == before ]]; then export EXPANSE_CUDA_SITES_COPY=before; else unset EXPANSE_CUDA_SITES_COPY; fi
  EXPANSE_CUDA_STAR_TIMELINE=1 timeout 90 $B --sizes 4096 --dists kuzmin --reps 3 2>$OUT/t.err | python3 -c "
import sys,json
for l in sys.stdin:
  r=json.loads(l); s=r['pipeline_device_stages_ms']; print('stars unpiped', r['device_stages_ms'].get('stars'), 'piped', s.get('stars'), 'GPU-only', round(sum(v for k,v in s.items() if k not in ('upload','download')),2))"
  grep "star stage timeline" $OUT/t.err | tail -4 || head -5 $OUT/t.err
done > $OUT/call4-copies.txt 2>&1
cat $OUT/call4-copies.txt; rm -f $OUT/t.err
