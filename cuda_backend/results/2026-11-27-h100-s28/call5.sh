#!/usr/bin/env bash
# Session 28 call 5: is kuzmin's pipelined second phase (1.5 ms slower than on host-prepared
# sites, calls 3-4) a matter of where the pool places the stage's arrays? A throwaway allocation
# of EXPANSE_CUDA_PAD_MB held through the stage moves them.
set -u
python3 -c "import tarfile; tarfile.open('.devrun/bundle.tar.xz').extractall('.devrun')"
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
export LD_LIBRARY_PATH=$PWD/.devrun/lib
B=.devrun/expanse_bench_cuda
for dist in kuzmin uniform; do for pad in 0 2 64 512 2048; do
  echo -n "$dist pad $pad MB: "
  EXPANSE_CUDA_PAD_MB=$pad timeout 90 $B --sizes 4096 --dists $dist --reps 3 | python3 -c "
import sys,json
for l in sys.stdin:
  r=json.loads(l); s=r['pipeline_device_stages_ms']; print('stars unpiped', r['device_stages_ms'].get('stars'), 'piped', s.get('stars'), 'GPU-only', round(sum(v for k,v in s.items() if k not in ('upload','download')),2))"
done; done > $OUT/call5-pads.txt 2>&1
cat $OUT/call5-pads.txt
