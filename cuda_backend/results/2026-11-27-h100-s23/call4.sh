#!/usr/bin/env bash
# Session 23 call 4: call 3's emit (StarView, staged triangles: emit 3.20 -> 2.50 ms at 4096^2
# uniform) with each triangle's place left in its neighbour words (no random rank look-up in the
# links' kernel; expected links -0.3 to -0.5 ms, the triangles' kernel +0.1), and the walks
# padding their rows' first sector (call 3's initcheck timed out on StarView's unwritten words;
# the star kernels should not move). Against c3f9ffe (baseline/), two rounds; ncu of the emit;
# CUDA tests, four sanitizers, conformance on CUDA.
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT .devrun/baseline/COMMIT
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $OUT/call4-emit.jsonl; }
for round in 1 2; do
  for v in new base; do
    B=.devrun/expanse_bench_cuda; [ $v = base ] && B=.devrun/baseline/expanse_bench_cuda
    timeout 150 $B --sizes 4096 --dists uniform,gaussian,grid,kuzmin --reps 5 | tag $v
    timeout 60 $B --sizes 512 --dists uniform --reps 7 | tag $v
  done
done
python3 - $OUT/call4-emit.jsonl <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'], r['side'], r['variant'])].append('%.2f (stars %.2f, emit %.2f, audit %.2f, h2h %.1f, tri %d, def %d)'%(g, s.get('stars',0), s.get('emit',0), s.get('audit',0), r.get('host_to_host_ms',0), r['triangles'], r['deferred']))
for k in sorted(d): print(*k, ' / '.join(d[k]))
PY
timeout 200 /usr/local/cuda/bin/ncu --kernel-name regex:"emit_" --launch-skip 2 --launch-count 2 --set full \
  .devrun/expanse_bench_cuda --sizes 4096 --dists uniform --reps 1 --no-pipeline > $OUT/call4-ncu-emit.txt 2>&1; echo "ncu rc $?"
grep -E "  [a-z_ ]*unnamed|Duration|DRAM Throughput|L1/TEX Cache Throughput|L2 Cache Throughput|L2 Compression Input" $OUT/call4-ncu-emit.txt | cut -c1-120
timeout 150 .devrun/expanse_cuda_tests > $OUT/call4-cuda-tests.log 2>&1; echo "cuda tests rc $?"; tail -1 $OUT/call4-cuda-tests.log
for tool in memcheck racecheck initcheck synccheck; do
  timeout 150 /usr/local/cuda/bin/compute-sanitizer --tool $tool --error-exitcode 9 .devrun/expanse_cuda_tests --small > /tmp/san.log 2>&1; echo "$tool rc $?"; tail -1 /tmp/san.log; (echo "=== $tool"; cat /tmp/san.log) >> $OUT/call4-sanitizers.log
done
timeout 150 .devrun/expanse_conformance --backend cuda > $OUT/call4-conformance.log 2>&1; echo "conformance rc $?"; tail -2 $OUT/call4-conformance.log
