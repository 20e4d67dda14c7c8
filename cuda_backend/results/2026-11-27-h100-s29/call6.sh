#!/usr/bin/env bash
# Session 29 call 6: G (the bundle's build, ab9cb05): why the 4096^2 lattice is 0.6 ms slower
# (call 5) when ptxas -v gives 7 of its 9 kernels the resources they had: the lattice kernels'
# SASS in G's star_kernels.cu.o against 3d731e3's (their .nv_fatbin sections, objs/), and the
# lattice's star stage timelines, both builds.
set -u
python3 -c "import tarfile; tarfile.open('.devrun/bundle.tar.xz').extractall('.devrun')"
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT; nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
CO=$(ls /usr/local/cuda/bin/cuobjdump 2>/dev/null || command -v cuobjdump)
echo "cuobjdump: $CO"
for v in g base; do $CO -sass .devrun/objs/${v}_star_kernels.fatbin > /tmp/$v.sass 2>/dev/null; done
python3 - <<'PY' | tee $OUT/call6-sass.txt
import re
def funcs(f):
    d={}; cur=None; buf=[]
    for l in open(f):
        m=re.match(r'\s+Function : (\S+)',l)
        if m:
            if cur: d[cur]=buf
            cur=re.sub(r'_GLOBAL__N__[0-9a-f]+_\d+_star_kernels_cu_[0-9a-f]+','ANON',m.group(1)); buf=[]; continue
        if cur:
            m2=re.match(r'\s+/\*[0-9a-f]+\*/\s+(.*?)\s*;',l)
            if m2: buf.append(re.sub(r'_GLOBAL__N__[0-9a-f]+_\d+_star_kernels_cu_[0-9a-f]+','ANON',m2.group(1)))
    if cur: d[cur]=buf
    return d
g=funcs('/tmp/g.sass'); b=funcs('/tmp/base.sass')
print('functions', len(g), len(b))
for k in sorted(g):
    m=re.search(r'(star_kernel|star_list_kernel|star_retry_kernel)ILNS1_10StarSearchE1ELi(\d)ELb(\d)(\w*?)EEEv',k)
    if not m: continue
    same = g[k]==b.get(k)
    print(m.group(1), 'blocks', m.group(2), 'lattice' if m.group(3)=='1' else 'other', m.group(4), len(g[k]), len(b.get(k,[])), 'IDENTICAL' if same else 'differs')
PY
B=.devrun/expanse_bench_cuda O=.devrun/baseline/expanse_bench_cuda
for b in G:$B base:$O G:$B base:$O; do
  echo "== grid ${b%%:*}"; EXPANSE_CUDA_STAR_TIMELINE=1 timeout 60 ${b#*:} --sizes 4096 --dists grid --reps 2 2>&1 >/dev/null | grep "star stage" | tail -2
done | tee $OUT/call6-timeline.txt
