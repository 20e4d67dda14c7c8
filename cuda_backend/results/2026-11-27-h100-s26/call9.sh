#!/usr/bin/env bash
# Session 26 call 9: where the device preparation's time goes on kuzmin and uniform 4096^2 (the
# pipeline, as the benchmark runs it): ncu's SpeedOfLight on every kernel of the preparation
# (codes, sorts, the duplicates' merge), the warm-up's and the measured run's (c77244f).
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT
B=.devrun/expanse_bench_cuda
K='regex:morton|short_|gather_scaled|long_run|first_equal|run_start|run_length|hash_|compact_kernel|representative|hull_sites|DeviceRadixSort|DeviceScan|DeviceSegmented'
for dist in kuzmin uniform; do
  timeout 200 /usr/local/cuda/bin/ncu --section SpeedOfLight -k "$K" --launch-count 120 \
    $B --sizes 4096 --dists $dist --reps 1 > $OUT/call9-ncu-$dist.txt 2>&1; echo "ncu $dist rc $?"
done
python3 - $OUT <<'PY'
import re,sys,os
for dist in ('kuzmin','uniform'):
    txt=open(os.path.join(sys.argv[1],'call9-ncu-%s.txt'%dist)).read()
    rows=[]
    for b in re.split(r'\n  (?=\S)', txt):
        head=b.split('\n')[0]
        m=re.search(r'Duration\s+(\S+)\s+([\d.,]+)', b)
        if not m: continue
        v=float(m.group(2).replace(',','')); u=m.group(1)
        us=v/1000 if u=='ns' else v if u=='us' else v*1000
        name=re.sub(r'<.*','',re.sub(r'\(.*','',head)).split('::')[-1]
        rows.append((name,us))
    print('==',dist,len(rows),'kernels, total %.0f us'%sum(r[1] for r in rows))
    for n,us in rows: print('  %8.1f us  %s'%(us,n))
PY
