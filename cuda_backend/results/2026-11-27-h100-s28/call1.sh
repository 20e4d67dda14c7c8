#!/usr/bin/env bash
# Session 28 call 1: N (the bundle's build, 40723aa): the second phase's retries walked at once by
# their warps (star_list_kernel's RetryHere), adaptive sort keys for clustered inputs, the merge's
# scan skipped where no point repeats; N with EXPANSE_CUDA_PHASE_RETRY=end (the retries after the
# phase, as before); against session 27's final build (baseline/, 3e734c0). 4096^2 every input,
# two rounds alternated; 512^2 to 2048^2; kuzmin's timelines; N's CUDA tests.
set -u
bash bench/device/run-on-device.sh env > $OUT/call1-env.txt 2>&1
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT .devrun/baseline/COMMIT
J=$OUT/call1-compare.jsonl
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $J; }
B=.devrun/expanse_bench_cuda O=.devrun/baseline/expanse_bench_cuda
for round in 1 2; do
  timeout 150 $B --sizes 4096 --dists uniform,gaussian,grid,kuzmin --reps 5 | tag N
  EXPANSE_CUDA_PHASE_RETRY=end timeout 150 $B --sizes 4096 --dists gaussian,kuzmin --reps 5 | tag N-end
  timeout 150 $O --sizes 4096 --dists uniform,gaussian,grid,kuzmin --reps 5 | tag base
done
timeout 120 $B --sizes 512,1024,2048 --dists uniform,gaussian,grid,kuzmin --reps 7 | tag N
timeout 120 $O --sizes 512,1024,2048 --dists uniform,gaussian,grid,kuzmin --reps 7 | tag base
python3 - $J <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'], r['side'], r['variant'])].append('%.2f (sort %.2f merge %.2f bucket %.2f stars %.2f, def %d, seam %.4f%%, h2h %.1f, %s)'%(g,s.get('sort',0),s.get('merge duplicates',0),s.get('bucket',0),s.get('stars',0),r['deferred'],100*r.get('seam_share',0),r.get('host_to_host_ms',0),'adaptive' if r.get('adaptive_morton_sort') else 'short' if r.get('short_morton_sort') else 'full'))
for k in sorted(d): print(*k, ' / '.join(d[k]))
PY
for b in N:$B base:$O; do for dist in gaussian kuzmin; do
  echo "== timeline $dist ${b%%:*}"
  EXPANSE_CUDA_STAR_TIMELINE=1 timeout 60 ${b#*:} --sizes 4096 --dists $dist --reps 2 2>&1 >/dev/null | grep "star stage" | tail -2
done; done > $OUT/call1-timeline.txt 2>&1
cat $OUT/call1-timeline.txt
timeout 200 .devrun/expanse_cuda_tests > $OUT/call1-cuda-tests.log 2>&1; echo "cuda tests rc $?"; grep -E "^FAIL|preparation" $OUT/call1-cuda-tests.log | head -20; tail -1 $OUT/call1-cuda-tests.log
# The preparation's and bucketing's kernels one by one (ncu, serialised), kuzmin 4096^2, N and base.
for b in N:$B base:$O; do
  echo "== ncu kuzmin ${b%%:*}"
  timeout 100 ncu -c 150 --metrics gpu__time_duration.sum --print-units base --csv -k 'regex:^(?!star_|edge_|inbox_|emit_|audit_|copy_count|boundary_strips).*' \
    ${b#*:} --sizes 4096 --dists kuzmin --reps 1 2>/dev/null | python3 -c "
import sys,csv,collections
rows=[r for r in csv.reader(l for l in sys.stdin if l.startswith('\"'))]
h=rows[0]; ki=h.index('Kernel Name'); vi=h.index('Metric Value'); ii=h.index('ID')
t=collections.OrderedDict()
for r in rows[1:]:
  name=r[ki].split('(')[0][:60]; t.setdefault(name,[]).append(float(r[vi].replace(',',''))/1e6)
for k,v in t.items(): print('%-60s n=%d med %.3f ms sum/run %.3f'%(k,len(v),sorted(v)[len(v)//2],sum(v)/2))
"
done > $OUT/call1-ncu.txt 2>&1
cat $OUT/call1-ncu.txt
