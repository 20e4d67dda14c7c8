#!/usr/bin/env bash
# Session 34 call 3: every kernel's duration in one 4096^2 uniform triangulation (ncu,
# gpu__time_duration; HEAD's build, 9bc5ffa's code), to see what the stages outside the stars
# are made of.
set -u
bash bench/device/run-on-device.sh env > /dev/null 2>&1; rm -f $OUT/env.txt
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT
timeout 300 /usr/local/cuda/bin/ncu --metrics gpu__time_duration.sum --csv .devrun/expanse_bench_cuda --sizes 4096 --dists uniform --reps 1 > $OUT/call3-ncu-durations.csv 2>$OUT/call3-ncu.stderr
echo "ncu rc $?"
python3 - $OUT/call3-ncu-durations.csv <<'PY'
import csv,sys,collections,re
rows=[r for r in csv.reader(open(sys.argv[1])) if len(r)>10]
h=rows[0]; c={k:i for i,k in enumerate(h)}
tot=collections.defaultdict(float); cnt=collections.Counter()
for r in rows[1:]:
  if r[c['Metric Name']]!='gpu__time_duration.sum': continue
  name=re.sub(r'\(.*','',r[c['Kernel Name']])[:90]
  v=float(r[c['Metric Value']].replace(',',''))
  unit=r[c['Metric Unit']]
  v = v/1e3 if unit=='usecond' else v/1e6 if unit=='nsecond' else v
  tot[name]+=v; cnt[name]+=1
for k,v in sorted(tot.items(), key=lambda x:-x[1]): print('%9.3f ms %4d  %s'%(v,cnt[k],k))
PY
