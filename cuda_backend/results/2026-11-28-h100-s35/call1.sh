#!/usr/bin/env bash
# Session 35 call 1: every kernel's duration in one 4096^2 kuzmin triangulation and one uniform
# (ncu, gpu__time_duration; HEAD 4732f34), to see where kuzmin's stages outside the stars
# (merge 0.83 ms against 0.07, sort 2.25 against 1.55, bucket 1.65 against 1.05) spend it.
set -u
bash bench/device/run-on-device.sh env > /dev/null 2>&1; cp $OUT/env.txt $OUT/call1-env.txt 2>/dev/null; rm -f $OUT/env.txt
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT
B=.devrun/expanse_bench_cuda
for d in kuzmin uniform; do
timeout 200 /usr/local/cuda/bin/ncu --metrics gpu__time_duration.sum --csv $B --sizes 4096 --dists $d --reps 1 > $OUT/call1-ncu-$d.csv 2>$OUT/call1-ncu-$d.stderr
echo "ncu $d rc $?"
python3 - $OUT/call1-ncu-$d.csv <<'PY'
import csv,sys,collections,re
rows=[r for r in csv.reader(open(sys.argv[1])) if len(r)>10]
h=rows[0]; c={k:i for i,k in enumerate(h)}
seq=[]
for r in rows[1:]:
  if r[c['Metric Name']]!='gpu__time_duration.sum': continue
  name=re.sub(r'\(.*','',r[c['Kernel Name']])[:80]
  v=float(r[c['Metric Value']].replace(',',''))
  unit=r[c['Metric Unit']]
  v = v/1e3 if unit=='usecond' else v/1e6 if unit=='nsecond' else v
  seq.append((name,v))
# the second triangulation only (the first is the warm-up): split at the second morton/short key kernel
starts=[i for i,(n,v) in enumerate(seq) if 'morton_kernel' in n or 'short_key_kernel' in n]
s=starts[-1] if starts else 0
print('kernels from', s, 'of', len(seq))
for i,(n,v) in enumerate(seq[s:s+60]): print('%3d %8.3f ms  %s'%(i,v,n))
tot=collections.defaultdict(float); cnt=collections.Counter()
for n,v in seq[s:]: tot[n]+=v; cnt[n]+=1
for k,v in sorted(tot.items(), key=lambda x:-x[1])[:40]: print('%9.3f ms %4d  %s'%(v,cnt[k],k))
PY
done
xz -T4 $OUT/*.csv
