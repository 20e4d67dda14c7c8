#!/usr/bin/env bash
# Session 31 call 8: the SASS of the lattice's and uniform cells' first-phase star kernels in
# the final build (aa54492) and session 30's (ef097ed), to find what costs the lattice 0.75 ms
# and uniform inputs 0.2 (their walks compile their former code, their registers and stacks are
# the same); and the grid's and uniform's star timelines in both builds.
set -u
bash bench/device/run-on-device.sh env > /dev/null 2>&1; rm -f $OUT/env.txt
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT .devrun/baseline/COMMIT
for v in new base; do
  b=.devrun/expanse_bench_cuda; [ $v = base ] && b=.devrun/baseline/expanse_bench_cuda
  /usr/local/cuda/bin/cuobjdump -sass $b > /tmp/sass-$v.txt 2>/dev/null
  python3 - /tmp/sass-$v.txt $OUT/call8-sass-$v <<'PY'
import sys,re
text=open(sys.argv[1]).read()
funcs=re.split(r'\n\s*Function : ', text)
want={'lattice':'star_kernelILNS1_10StarSearchE1ELi6ELb1ELb0ELb0E','uniform8':'star_kernelILNS1_10StarSearchE1ELi8ELb0ELb0ELb0E'}
for tag,key in want.items():
  for f in funcs:
    if f.startswith('_ZN') and key in f.split('\n')[0]:
      body=re.sub(r'/\*[0-9a-f]{4,}\*/','',f)
      body=re.sub(r'/\* 0x[0-9a-f]+ \*/','',body)
      open(sys.argv[2]+'-'+tag+'.txt','w').write(body)
      print(tag, len(body.splitlines()))
      break
PY
done
for v in new base; do
  b=.devrun/expanse_bench_cuda; [ $v = base ] && b=.devrun/baseline/expanse_bench_cuda
  for dist in grid uniform; do
    echo "== $v $dist"; EXPANSE_CUDA_STAR_TIMELINE=1 timeout 40 $b --sizes 4096 --dists $dist --reps 3 2>&1 >/dev/null | grep "star stage timeline" | tail -1
  done
done | tee $OUT/call8-timelines.txt
