#!/usr/bin/env bash
# Runs Expanse's benchmarks; bench/report.py turns the results into docs/benchmarks.md and plots.
#
#   bench/run.sh --quick            under a minute on a 2-core machine with lavapipe or CPU only;
#                                   results and a report of them (report/) go to bench/out/quick/.
#                                   CI runs this so the benchmark programs and the report cannot rot.
#   bench/run.sh --full             real numbers; results and a report of them alone (report/)
#                                   go to bench/out/<date>-<host>/.
#   bench/run.sh --full --publish   ... then folded into bench/data/ (the newest measurement of
#                                   each configuration) and docs/benchmarks.md regenerated.
#
# Options:
#   --build-dir DIR       build tree (configured here if it has none; default: build-bench)
#   --no-build            use the programs already built in --build-dir
#   --experiments LIST    comma list of peers,threads,scaling,pictures,star_work (default: all)
#   --gpu LIST            GPU backends to try (default: vulkan,cuda; missing ones are skipped
#                         with a record that says why)
#   --dist LIST           distributions for peers/scaling/pictures (default: uniform,gaussian)
#   --commit ID           commit to record when the tree has no .git (a copied tree on another
#                         machine); otherwise the commit the programs were built from
#   --results DIR         where the JSON lines go (overrides the defaults above)
#   --note TEXT           stored in every record (say how loaded the machine was)
#   --max-n N             leave out sizes above N (e.g. 65536 for lavapipe; accepts 256^2, 1e6)
#   --timeout SECONDS     kill an experiment that runs longer (quick: 45, full: 3000)
#   --publish             (--full) merge the results into bench/data/ and regenerate docs/
#   --no-report           only measure
# Each experiment is one expanse-bench invocation, so a machine with a per-command time limit
# can run them one at a time (--experiments scaling, then --experiments threads, ...).
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/.." && pwd)"
mode=""
build_dir="$root/build-bench"
build=1
report=1
publish=0
experiments="peers,threads,scaling,pictures,star_work"
gpu="vulkan,cuda"
results=""
note=""
dists="uniform,gaussian"
timeout_s=""
max_n=""

while [[ $# -gt 0 ]]; do
  case "$1" in
    --quick) mode=quick ;;
    --full) mode=full ;;
    --build-dir) build_dir="$(realpath -m "$2")"; shift ;;
    --no-build) build=0 ;;
    --experiments) experiments="$2"; shift ;;
    --gpu) gpu="$2"; shift ;;
    --results) results="$(realpath -m "$2")"; shift ;;
    --dist) dists="$2"; shift ;;
    --commit) export EXPANSE_COMMIT="$2"; shift ;;
    --note) note="$2"; shift ;;
    --no-report) report=0 ;;
    --publish) publish=1 ;;
    --timeout) timeout_s="$2"; shift ;;
    --max-n) max_n="$2"; shift ;;
    -h|--help) sed -n '2,29p' "$0"; exit 0 ;;
    *) echo "run.sh: unknown argument $1 (see --help)" >&2; exit 2 ;;
  esac
  shift
done
if [[ -z "$mode" ]]; then
  echo "run.sh: say --quick or --full (see --help)" >&2
  exit 2
fi
if [[ $publish -eq 1 && $mode != full ]]; then
  echo "run.sh: --publish takes a --full run's numbers only" >&2
  exit 2
fi

if [[ $build -eq 1 ]]; then
  if [[ ! -f "$build_dir/build.ninja" && ! -f "$build_dir/Makefile" ]]; then
    generator=()
    command -v ninja >/dev/null && generator=(-G Ninja)
    cmake -S "$root" -B "$build_dir" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release \
      -DEXPANSE_BUILD_BENCH=ON
  fi
  cmake --build "$build_dir" --target expanse_bench expanse_bench_peers expanse_bench_star_work -j"$(nproc)"
fi
bench="$build_dir/bench/expanse-bench"
star_work="$build_dir/bench/expanse-bench-star-work"
peers="$build_dir/bench/expanse-bench-peers"

# delaunator comes from npm at bench time; without network the records say it was skipped.
if command -v npm >/dev/null && [[ ! -d "$here/delaunator/node_modules/delaunator" ]]; then
  (cd "$here/delaunator" && npm ci --no-audit --no-fund --loglevel=error >/dev/null 2>&1) ||
    echo "run.sh: npm ci failed; delaunator will be skipped" >&2
fi

if [[ -z "$results" ]]; then
  if [[ $mode == quick ]]; then
    results="$here/out/quick"
    rm -rf "$results"
  else
    results="$here/out/$(date -u +%Y-%m-%d)-$(hostname -s)"
  fi
fi
mkdir -p "$results"
# A backend under construction can hang or run away with memory; CI must still finish.
[[ -z "$timeout_s" ]] && timeout_s=$([[ $mode == quick ]] && echo 45 || echo 3000)

load="$(cut -d' ' -f1-3 /proc/loadavg 2>/dev/null || true)"
[[ -z "$note" ]] && note="load average at start: $load"
gpu_and_cpu="cpu,$gpu"

# A crash in one experiment (a backend under construction) must not throw away the others: the
# records written so far stay (one flushed line per configuration), the next experiment runs, and
# the script still fails at the end so CI notices.
failed=()
run() {  # run EXPERIMENT ARGS...: one expanse-bench invocation appending to EXPERIMENT.jsonl
  local experiment="$1"
  shift
  echo "== $experiment" >&2
  local status=0
  timeout --kill-after=10 "$timeout_s" \
    "$bench" --experiment "$experiment" --note "$note" -o "$results/$experiment.jsonl" "$@" ||
    status=$?
  if [[ $status -ne 0 ]]; then
    echo "run.sh: experiment $experiment failed (exit status $status)" >&2
    failed+=("$experiment")
  fi
}

has() { [[ ",$experiments," == *",$1,"* ]]; }

count_star_work() {  # the CUDA kernel's work counted on the CPU (bench/src/star_work.cpp)
  echo "== star_work" >&2
  timeout --kill-after=10 "$timeout_s" "$star_work" --note "$note" -o "$results/star_work.jsonl" "$@" ||
    { echo "run.sh: experiment star_work failed" >&2; failed+=(star_work); }
}

count() {  # count 4096^2 | 1e6 | 1000: the number of points a size stands for
  local s="$1"
  if [[ $s == *^* ]]; then echo $(( ${s%^*} ** ${s#*^} ))
  elif [[ $s == *e* ]]; then echo $(( ${s%e*} * 10 ** ${s#*e} ))
  else echo "$s"; fi
}

sizes() {  # sizes LIST: LIST without the sizes above --max-n
  local kept=() s
  for s in ${1//,/ }; do
    if [[ -z "$max_n" ]] || (( $(count "$s") <= $(count "$max_n") )); then kept+=("$s"); fi
  done
  local IFS=,
  echo "${kept[*]}"
}

if [[ $mode == quick ]]; then
  "$peers" 2e4 || failed+=(peers-selfcheck)
  has peers && run peers --backends "$gpu_and_cpu,cgal,qhull,delaunator" \
    --dist "$dists" -n "$(sizes 1e3,1e4)" --layouts default,paper --warmup 1 -r 3 --max-seconds 1
  has threads && run threads --backends "$gpu" --dist uniform -n "$(sizes 32^2,64^2)" --layouts paper \
    --threads 4,8,16,32 --warmup 1 -r 1
  has scaling && run scaling --backends "$gpu_and_cpu,cgal" --dist "$dists" \
    -n "$(sizes 32^2,64^2,128^2)" --layouts default,paper --warmup 1 -r 3 --max-seconds 1
  has pictures && run pictures --backends "$gpu,cpu" --dist "$dists" -n "$(sizes 32^2)" \
    --layouts paper,default --warmup 0 -r 1 --pictures "$results/pictures"
  has star_work && count_star_work --dist uniform,gaussian,kuzmin --n "$(sizes 1e4)"
else
  has peers && run peers --backends "$gpu_and_cpu,cgal,qhull,delaunator" \
    --dist "$dists" -n "$(sizes 1e4,1e5,1e6)" --layouts default,paper --warmup 1 -r 5 \
    --max-seconds 60
  # Fig. IV.1: the paper's sizes, threads per block in powers of two around sqrt(n/256).
  has threads && run threads --backends "$gpu" --dist uniform -n "$(sizes 256^2,512^2,1024^2,2048^2)" \
    --layouts paper --threads 8,16,32,64,128,256,512,1024 --warmup 1 -r 3 --max-seconds 10
  # Figs. IV.2/IV.3 and the iteration counts: n = 32^2 ... 4096^2.
  has scaling && run scaling --backends "$gpu_and_cpu,cgal" --dist "$dists" \
    -n "$(sizes 32^2,64^2,128^2,256^2,512^2,1024^2,2048^2,4096^2)" --layouts default,paper --warmup 1 -r 5 \
    --max-seconds 30
  # Counts, not times: any machine gives the same numbers.
  has star_work && count_star_work --dist uniform,gaussian,kuzmin,grid --n "$(sizes 1e6,4e6)" --search boxes,rings
  # Only device backends: the CPU backend's picture would be all seam.
  has pictures && [[ -n "$gpu" ]] && run pictures --backends "$gpu" --dist "$dists" \
    -n "$(sizes 32^2)" --layouts paper,default --warmup 0 -r 1 --pictures "$results/pictures"
fi

# Debian's python3-matplotlib lives under /usr/bin/python3; a pyenv or venv python3 earlier on
# PATH may lack it.
python=""
for candidate in python3 /usr/bin/python3; do
  if "$candidate" -c "import matplotlib" 2>/dev/null; then python="$candidate"; break; fi
done
if [[ $report -eq 1 && -z "$python" ]]; then
  echo "run.sh: no python3 with matplotlib (apt-get install python3-matplotlib)" >&2
  exit 1
fi
if [[ $report -eq 1 ]]; then
  # The report of this run alone, beside its results; docs/ only through --publish.
  "$python" "$here/report.py" --data "$results" --docs "$results/report"
  if [[ $publish -eq 1 ]]; then
    "$python" "$here/report.py" --merge "$results" --data "$here/data" --docs "$root/docs"
  fi
fi
echo "run.sh: results in $results" >&2
if [[ ${#failed[@]} -gt 0 ]]; then
  echo "run.sh: FAILED experiments: ${failed[*]}" >&2
  exit 1
fi
