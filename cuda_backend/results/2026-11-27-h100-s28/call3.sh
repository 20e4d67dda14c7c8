#!/usr/bin/env bash
# Session 28 call 3: where kuzmin's pipelined star stage spends the 1.5 ms it does not spend on
# the host-prepared sites: timelines with a mark at the stage's start ("stage"), every run's.
set -u
python3 -c "import tarfile; tarfile.open('.devrun/bundle.tar.xz').extractall('.devrun')"
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT; nvidia-smi --query-gpu=name,driver_version --format=csv,noheader; ls /usr/local/cuda/bin | grep -i nsys
B=.devrun/expanse_bench_cuda
for dist in kuzmin uniform gaussian; do
  echo "== $dist"
  EXPANSE_CUDA_STAR_TIMELINE=1 timeout 90 $B --sizes 4096 --dists $dist --reps 2 2>$OUT/t.err | python3 -c "
import sys,json
for l in sys.stdin:
  r=json.loads(l); print('stars unpiped', r['device_stages_ms'].get('stars'), 'piped', r['pipeline_device_stages_ms'].get('stars'))"
  grep "star stage timeline" $OUT/t.err || head -5 $OUT/t.err
done > $OUT/call3-timelines.txt 2>&1
cat $OUT/call3-timelines.txt; rm -f $OUT/t.err
