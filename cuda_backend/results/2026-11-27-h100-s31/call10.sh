#!/usr/bin/env bash
# Session 31 call 10: T (the bundle's build: call 9's, the row loop testing its line before `part`, as
# before the scans across) against session 30's final code (baseline/, ef097ed): 4096^2 every
# input, two rounds alternated; the SASS of the lattice's first-phase kernel in both; the grid's,
# uniform's and kuzmin's star timelines.
set -u
bash bench/device/run-on-device.sh env > /dev/null 2>&1; cp $OUT/env.txt $OUT/call10-env.txt 2>/dev/null; rm -f $OUT/env.txt
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT .devrun/baseline/COMMIT
J=$OUT/call10-compare.jsonl
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $J; }
B=.devrun/expanse_bench_cuda O=.devrun/baseline/expanse_bench_cuda
for round in 1 2; do
  timeout 120 $B --sizes 4096 --dists uniform,gaussian,grid,kuzmin --reps 5 | tag T
  timeout 120 $O --sizes 4096 --dists uniform,gaussian,grid,kuzmin --reps 5 | tag base
done
for v in new base; do
  b=$B; [ $v = base ] && b=$O
  /usr/local/cuda/bin/cuobjdump -sass $b > /tmp/sass-$v.txt 2>/dev/null
  python3 - /tmp/sass-$v.txt /tmp/lattice-$v.txt <<'PY'
import sys,re
funcs=re.split(r'\n\s*Function : ', open(sys.argv[1]).read())
for f in funcs:
  if f.startswith('_ZN') and 'star_kernelILNS1_10StarSearchE1ELi6ELb1ELb0ELb0E' in f.split('\n')[0]:
    body='\n'.join(re.sub(r'0x[0-9a-f]+','X',l.strip()) for l in f.split('\n')[1:])
    open(sys.argv[2],'w').write(body); break
PY
done
echo "lattice first-phase SASS lines differing: $(diff /tmp/lattice-new.txt /tmp/lattice-base.txt | grep -c '^[<>]')" | tee $OUT/call10-sass-diff.txt
diff /tmp/lattice-new.txt /tmp/lattice-base.txt | head -300 > $OUT/call10-sass-diff-head.txt
python3 - $J <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'], r['side'], r['variant'])].append('%.2f (stars %.2f, bucket %.2f, def %d, seam %.4f%%)'%(g,s.get('stars',0),s.get('bucket',0),r['deferred'],100*r.get('seam_share',0)))
for k in sorted(d): print(*k, ' / '.join(d[k]))
PY
for v in T base; do
  b=$B; [ $v = base ] && b=$O
  for dist in grid uniform kuzmin; do
    echo "== $v $dist"; EXPANSE_CUDA_STAR_TIMELINE=1 timeout 40 $b --sizes 4096 --dists $dist --reps 3 2>&1 >/dev/null | grep "star stage timeline" | tail -1
  done
done | tee $OUT/call10-timelines.txt
timeout 150 .devrun/expanse_cuda_tests > $OUT/call10-cuda-tests.log 2>&1; echo "cuda tests rc $?"; grep -E "^FAIL" $OUT/call10-cuda-tests.log | head; tail -1 $OUT/call10-cuda-tests.log
