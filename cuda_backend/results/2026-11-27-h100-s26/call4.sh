#!/usr/bin/env bash
# Session 26 call 4: the second phase's searching sites walked in rounds of one search each, the
# last without a limit (star_round_kernel, EXPANSE_CUDA_PHASE1_ROUNDS 1 = one walk each, 2, 3,
# 4), 4096^2 uniform, gaussian and kuzmin, two rounds alternated; the second phase at 4 blocks a
# multiprocessor on quantile cells (8,4,8; kuzmin's phase spilled 175 M requests at 64 registers,
# call 3); timelines; CUDA tests.
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT
J=$OUT/call4-rounds.jsonl
tag() { python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$1'; print(json.dumps(r))" >> $J; }
B=.devrun/expanse_bench_cuda
D="--sizes 4096 --dists uniform,gaussian,kuzmin --reps 5"
for round in 1 2; do
  for r in 1 2 3 4; do EXPANSE_CUDA_PHASE1_ROUNDS=$r timeout 120 $B $D | tag rounds$r; done
done
EXPANSE_CUDA_BLOCKS_PER_SM=8,4,8 timeout 100 $B --sizes 4096 --dists gaussian,kuzmin --reps 5 | tag blocks848
EXPANSE_CUDA_PHASE1_ROUNDS=3 EXPANSE_CUDA_BLOCKS_PER_SM=8,4,8 timeout 100 $B --sizes 4096 --dists gaussian,kuzmin --reps 5 | tag rounds3-blocks848
python3 - $J <<'PY'
import json,sys,collections
d=collections.defaultdict(list)
for l in open(sys.argv[1]):
  r=json.loads(l)
  s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  d[(r['distribution'], r['side'], r['variant'])].append('%.2f (stars %.2f, def %d)'%(g,s.get('stars',0),r['deferred']))
for k in sorted(d): print(*k, ' / '.join(d[k]))
PY
for dist in uniform kuzmin; do
  for r in 1 3; do
    echo "== timeline $dist rounds=$r"
    EXPANSE_CUDA_PHASE1_ROUNDS=$r EXPANSE_CUDA_STAR_TIMELINE=1 timeout 60 $B --sizes 4096 --dists $dist --reps 2 2>&1 >/dev/null | grep "star stage" | tail -2
  done
done > $OUT/call4-timeline.txt 2>&1
cat $OUT/call4-timeline.txt
timeout 200 .devrun/expanse_cuda_tests > $OUT/call4-cuda-tests.log 2>&1; echo "cuda tests rc $?"; tail -1 $OUT/call4-cuda-tests.log
