#!/usr/bin/env bash
# Session 15 call 5: the final code (4dfd46b): conformance on CUDA with two phases at every size, the sanitizers on the small cases (two phases among them), per-kernel times under ncu at 4096^2, host to host against 6acdfcb.
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
EXPANSE_CUDA_PHASES=2 timeout 300 .devrun/expanse_conformance --backend cuda > $OUT/call5-conformance-two-phases.log 2>&1; echo "conformance (two phases) rc $?"
tail -2 $OUT/call5-conformance-two-phases.log
for tool in memcheck racecheck initcheck synccheck; do
  timeout 240 /usr/local/cuda/bin/compute-sanitizer --tool $tool --error-exitcode 9 .devrun/expanse_cuda_tests --small > $OUT/call5-sanitizer-$tool.log 2>&1; echo "$tool rc $?"; tail -1 $OUT/call5-sanitizer-$tool.log
done
for d in uniform kuzmin; do
  timeout 200 /usr/local/cuda/bin/ncu --kernel-name regex:"star|emit|audit" --metrics gpu__time_duration.sum --csv \
    .devrun/expanse_bench_cuda --sizes 4096 --dists $d --reps 1 --no-pipeline > $OUT/call5-ncu-$d.csv 2>/dev/null; echo "ncu $d rc $?"
  python3 - $OUT/call5-ncu-$d.csv <<'PY'
import csv,sys,collections,re
rows=[r for r in csv.reader(open(sys.argv[1])) if len(r)>10]
hdr=rows[0]; ki=hdr.index('Kernel Name'); vi=hdr.index('Metric Value'); ii=hdr.index('ID')
seen=collections.OrderedDict()
for r in rows[1:]:
  name=re.sub(r'\(.*','',r[ki]).split('::')[-1].split('<')[0]
  tmpl=re.search(r'<(.*)>',r[ki]); key=name+('<'+tmpl.group(1)[-40:]+'>' if tmpl else '')
  seen.setdefault(key,[]).append(float(r[vi].replace(',',''))/1e6)
for k,v in seen.items(): print(f"  {k[:90]:90} n={len(v)} last={v[-1]:.2f} ms")
PY
done
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $OUT/call5-h2h.jsonl; }
for round in 1 2 3; do
  timeout 150 .devrun/baseline/expanse_bench_cuda --sizes 4096 --dists uniform,kuzmin --reps 5 | tag base-$round
  timeout 150 .devrun/expanse_bench_cuda --sizes 4096 --dists uniform,kuzmin --reps 5 | tag new-$round
done
python3 - $OUT/call5-h2h.jsonl <<'PY'
import json,sys
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  gpu=sum(v for k,v in s.items() if k not in ('upload','download'))
  print(f"{r['variant']:7} {r['distribution'][:5]:5} {r['side']:5} h2h {r['host_to_host_ms']:7.1f} g {gpu:6.2f} st {s.get('stars',0):6.2f} dl {s.get('download',0):5.1f} d {r.get('deferred')} t {r.get('triangles')}")
PY
