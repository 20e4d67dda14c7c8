#!/usr/bin/env bash
# Session 25 call 1 (e87804a's bundle): what makes kuzmin 2x uniform when the CPU count says
# 1.41x (work a site 89.5 against 63.7 on quantile cells, 4096^2)? Uniform on its own cells
# against uniform forced onto quantile cells (EXPANSE_CUDA_GRID=quantile) and kuzmin: GPU-only,
# timelines, and ncu's full set on the first phase's kernel (star_kernel) of each.
# Expected: if uniform on quantile cells is near kuzmin, the quantile machinery is the cost; if
# near 29 ms, kuzmin's cells (crowded diagonals, empty axes) are.
set -u
bash bench/device/run-on-device.sh env >/dev/null
export LD_LIBRARY_PATH=$PWD/.devrun/lib
cat .devrun/COMMIT
B=.devrun/expanse_bench_cuda
J=$OUT/call1-grids.jsonl
run() {  # variant dist env...
  local v=$1 d=$2; shift 2
  echo "== $v $d"
  env "$@" EXPANSE_CUDA_STAR_TIMELINE=1 timeout 100 $B --sizes 4096 --dists $d --reps 5 2>/tmp/tl.txt | python3 -c "
import sys,json
for l in sys.stdin:
  try: r=json.loads(l)
  except Exception: continue
  r['variant']='$v'; s=r.get('pipeline_device_stages_ms') or {}
  g=sum(v for k,v in s.items() if k not in ('upload','download'))
  print('GPU-only %.2f stars %.2f bucket %.2f'%(g,s.get('stars',0),s.get('bucket',0)), file=sys.stderr)
  print(json.dumps(r))" >> $J
  grep -h "star stage" /tmp/tl.txt | tail -2
}
run default uniform X=1
run quantile uniform EXPANSE_CUDA_GRID=quantile
run default kuzmin X=1
run default gaussian X=1
N=/usr/local/cuda/bin/ncu
for c in "uniform X=1" "uniform EXPANSE_CUDA_GRID=quantile" "kuzmin X=1"; do
  set -- $c
  echo "=== ncu $c" >> $OUT/call1-ncu.txt
  env $2 timeout 240 $N -k regex:"^star_kernel$" --launch-skip 1 --launch-count 1 --set full \
    $B --sizes 4096 --dists $1 --reps 1 --no-pipeline >> $OUT/call1-ncu.txt 2>&1; echo "ncu $c rc $?"
done
grep -E "===|Duration|Warp Cycles Per Issued|Avg. Active Threads Per Warp|L1/TEX Hit Rate|L2 Hit Rate|DRAM Throughput|Memory Throughput|Executed Ipc Active|Achieved Occupancy|Registers Per|No Eligible|Stall" $OUT/call1-ncu.txt | head -80
