#!/usr/bin/env bash
# Session 29 call 9: which phases the change moved: kuzmin's and gaussian's star stage timelines
# at 4096^2, G (the bundle's build, ab9cb05) and session 28's final code (baseline/), three runs
# each, alternated.
set -u
python3 -c "import tarfile; tarfile.open('.devrun/bundle.tar.xz').extractall('.devrun')"
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT; nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
B=.devrun/expanse_bench_cuda O=.devrun/baseline/expanse_bench_cuda
for dist in kuzmin gaussian; do
  for b in G:$B base:$O G:$B base:$O; do
    echo "== $dist ${b%%:*}"; EXPANSE_CUDA_STAR_TIMELINE=1 timeout 60 ${b#*:} --sizes 4096 --dists $dist --reps 3 2>&1 >/dev/null | grep "star stage timeline" | tail -3
  done
done | tee $OUT/call9-timelines.txt
