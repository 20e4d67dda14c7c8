#!/usr/bin/env bash
# Runs on the GPU machine (the `device` tool), in a copy of this checkout, with the programs that
# bench/device/bundle.sh put into .devrun/ and the loader packages in .gl/. Writes at most eight
# files under $OUT (the tool's limit): one log per step group and the benchmark JSON lines.
#
#   bash bench/device/run-on-device.sh STEP...
#
# Steps (each under its own time limit, so one hang cannot eat the whole command):
#   env          nvidia-smi, vulkan device list                 -> env.txt
#   tests        CUDA tests, conformance on CUDA and on Vulkan, the Vulkan test suites and the
#                interop test (an application's own device and buffers)
#                (Vulkan with the Khronos validation layer carried in .devrun/layers) -> tests.log
#   sanitizer    compute-sanitizer memcheck/racecheck/initcheck/synccheck on the small cases
#                                                                -> sanitizer.log
#   bench-cuda   expanse_bench_cuda 512^2 .. 4096^2 x 4 distributions
#                                                  -> bench-cuda[-TAG].jsonl (log: bench.log)
#   figures      the paper's experiments for docs/benchmarks.md within one 10-minute command:
#                scaling 32^2..4096^2 on CUDA and Vulkan (our layout), the paper's layout and
#                the CPU backend and CGAL up to 1024^2, threads per block up to 1024^2
#                                                                -> results/{scaling,threads}.jsonl
#   compare      this build against the bundle's baseline/ (bundle.sh, EXPANSE_BASELINE),
#                alternated: star kernel and GPU-only     -> compare.jsonl (log: compare.log),
#                and the Vulkan backend at 4096^2 uniform -> compare-vulkan.jsonl
#   page-faults  expanse-bench-page-faults: faulting in 805 MB by thread count, huge pages or not
#                                                  -> page-faults.jsonl, printed
#   summary      a short table of the bench-cuda records, printed last (the tool returns the
#                end of the output)
# EXPANSE_BENCH_SIZES / EXPANSE_BENCH_DISTS / EXPANSE_BENCH_REPS narrow bench-cuda and compare,
# EXPANSE_BENCH_TAG names bench-cuda's output (for variants selected by environment variables),
# EXPANSE_BENCH_LIMIT is bench-cuda's time limit; EXPANSE_COMPARE_ROUNDS and
# EXPANSE_COMPARE_PIPELINE steer compare (docs/benchmarks.md, "Method", lists them all).
# The JSON lines become current numbers with `python3 bench/report.py --merge DIR --commit ...`.
set -u
cd "$(dirname "$0")/../.."
out="${OUT:-/tmp/expanse-device-out}"
mkdir -p "$out"
if [[ -f .devrun/bundle.tar.xz && ! -f .devrun/COMMIT ]]; then  # bench/device/bundle.sh's archive
  python3 -c 'import tarfile; tarfile.open(".devrun/bundle.tar.xz").extractall(".devrun")'
fi
for f in .gl/*.deb; do dpkg -x "$f" /; done
ldconfig
export LD_LIBRARY_PATH="$PWD/.devrun/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
nvidia_icd=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
[[ -f $nvidia_icd ]] && export VK_DRIVER_FILES="$nvidia_icd"
[[ -d .devrun/layers ]] && export VK_LAYER_PATH="$PWD/.devrun/layers"
bin=.devrun
commit="$(cat .devrun/COMMIT 2>/dev/null || echo unknown)"

# step NAME LIMIT LOG COMMAND...: runs COMMAND, appends its output to LOG, prints one status line.
step() {
  local name="$1" limit="$2" log="$3"
  shift 3
  local start=$SECONDS
  echo "===== $name: $*" >>"$log"
  timeout --kill-after=10 "$limit" "$@" >>"$log" 2>&1
  local rc=$?
  echo "===== $name: exit $rc after $((SECONDS - start)) s" >>"$log"
  printf '%-28s exit %3d  %4d s\n' "$name" "$rc" "$((SECONDS - start))"
}

for what in "$@"; do
  case "$what" in
    env)
      { date -u; nvidia-smi; nvidia-smi -q | grep -iE 'clocks|MHz|persistence|product name' | head -30
        nproc; free -g; echo "commit $commit"; "$bin/expanse" info; } >"$out/env.txt" 2>&1 ;;
    tests)
      log="$out/tests.log"
      step "cuda: backend" 300 "$log" "$bin/expanse_cuda_tests"
      step "conformance: cuda" 420 "$log" "$bin/expanse_conformance" --backend cuda
      EXPANSE_VULKAN_VALIDATION=1 step "conformance: vulkan" 420 "$log" "$bin/expanse_conformance" --backend vulkan
      EXPANSE_VULKAN_VALIDATION=1 step "vulkan: all suites" 300 "$log" "$bin/expanse_vulkan_tests" all
      step "vulkan: interop" 300 "$log" "$bin/expanse_vulkan_interop_tests"
      ;;
    sanitizer)
      log="$out/sanitizer.log"
      for tool in memcheck racecheck initcheck synccheck; do
        step "sanitizer $tool" 240 "$log" compute-sanitizer --tool "$tool" --error-exitcode 9 \
          "$bin/expanse_cuda_tests" --small
      done ;;
    bench-cuda)
      tag="${EXPANSE_BENCH_TAG:+-$EXPANSE_BENCH_TAG}"
      step "bench_cuda$tag" "${EXPANSE_BENCH_LIMIT:-540}" "$out/bench.log" sh -c "$bin/expanse_bench_cuda \
        --sizes ${EXPANSE_BENCH_SIZES:-512,1024,2048,4096} \
        --dists ${EXPANSE_BENCH_DISTS:-uniform,gaussian,grid,kuzmin} \
        --reps ${EXPANSE_BENCH_REPS:-5} > $out/bench-cuda$tag.jsonl" ;;
    compare)
      # This build against bundle.sh's baseline/, alternated EXPANSE_COMPARE_ROUNDS times (default
      # 2) so that drift on the host shows as a difference between rounds, not between builds:
      # star kernel and GPU-only (backend on host-prepared sites; with EXPANSE_COMPARE_PIPELINE=1
      # the pipeline's host-to-host times as well)                -> compare.jsonl; and the Vulkan
      # backend on NVIDIA's driver at 4096^2 uniform (expanse-bench)  -> compare-vulkan.jsonl.
      [[ -d $bin/baseline ]] || { echo "compare: no baseline/ in the bundle" >&2; exit 2; }
      parts="$out/compare-parts"
      only_backend=--no-pipeline
      [[ -n ${EXPANSE_COMPARE_PIPELINE:-} ]] && only_backend=
      mkdir -p "$parts"
      for round in $(seq "${EXPANSE_COMPARE_ROUNDS:-2}"); do
        for build in baseline current; do
          dir=$bin; [[ $build == baseline ]] && dir=$bin/baseline
          step "compare $build $round" 240 "$out/compare.log" sh -c "$dir/expanse_bench_cuda \
            --sizes ${EXPANSE_BENCH_SIZES:-512,4096} --dists ${EXPANSE_BENCH_DISTS:-uniform,gaussian,grid,kuzmin} \
            --reps ${EXPANSE_BENCH_REPS:-5} $only_backend > $parts/$build-$round.jsonl"
          EXPANSE_COMMIT="$(cat "$dir/COMMIT" 2>/dev/null || echo "$commit")" \
            step "compare vulkan $build $round" 120 "$out/compare.log" "$dir/expanse-bench" --backends vulkan \
            --dist uniform -n 4096^2 -r 3 --warmup 1 --note "compare: $build, round $round" -o "$out/compare-vulkan.jsonl"
        done
      done
      python3 - "$parts" "$out/compare.jsonl" "$(cat "$bin/baseline/COMMIT")" "$commit" <<'PY'
import glob, json, os, sys
parts, merged, commits = sys.argv[1], sys.argv[2], {"baseline": sys.argv[3], "current": sys.argv[4]}
with open(merged, "w") as out:
    for path in sorted(glob.glob(os.path.join(parts, "*.jsonl"))):
        build, round_ = os.path.basename(path)[:-6].split("-")
        for line in open(path):
            r = json.loads(line)
            r.update(build=build, round=int(round_), commit=commits[build])
            out.write(json.dumps(r) + "\n")
            if "error" in r:
                print(build, round_, r["distribution"], r["side"], "error:", r["error"]); continue
            print(f"{build:9} {round_} {r['distribution']:9} {r['side']:5} gpu {r['gpu_ms']:8.2f}"
                  f"  stars {r['device_stages_ms'].get('stars', 0):8.2f}  deferred {r['deferred']}"
                  + (f"  h2h {r['host_to_host_ms']:7.1f}  reused {r['host_to_host_reused_ms']:7.1f}"
                     if "host_to_host_ms" in r else ""))
PY
      rm -rf "$parts" ;;
    page-faults)
      step "page faults" 120 "$out/page-faults.log" sh -c "$bin/expanse-bench-page-faults --mib 805 \
        --threads 1,2,4,8,16 --reps 5 > $out/page-faults.jsonl"
      python3 - "$out/page-faults.jsonl" <<'PY'
import json, sys
for line in open(sys.argv[1]):
    r = json.loads(line)
    print(f"page faults {r['variant']:8} threads {r['threads']:2} huge {r['huge_pages']:2}: "
          f"{r['median_ms']:7.1f} ms  {r['gb_per_s']:5.1f} GB/s")
PY
      ;;
    figures)
      mkdir -p "$out/results"
      bench="$bin/expanse-bench"
      common=(--note "device run" --warmup 1)
      EXPANSE_COMMIT="$commit" step "scaling: GPU, our layout" 200 "$out/experiments.log" "$bench" \
        --experiment scaling --backends cuda,vulkan --dist uniform,gaussian \
        -n 32^2,64^2,128^2,256^2,512^2,1024^2,2048^2,4096^2 --layouts default -r 5 --max-seconds 8 \
        "${common[@]}" -o "$out/results/scaling.jsonl"
      EXPANSE_COMMIT="$commit" step "scaling: paper layout, CPU, CGAL" 130 "$out/experiments.log" "$bench" \
        --experiment scaling --backends cpu,cgal,cuda,vulkan --dist uniform,gaussian \
        -n 32^2,64^2,128^2,256^2,512^2,1024^2 --layouts paper -r 3 --max-seconds 5 \
        "${common[@]}" -o "$out/results/scaling.jsonl"
      EXPANSE_COMMIT="$commit" step "threads (Fig. IV.1)" 140 "$out/experiments.log" "$bench" \
        --experiment threads --backends cuda,vulkan --dist uniform -n 256^2,512^2,1024^2 --layouts paper \
        --threads 8,16,32,64,128,256,512,1024 -r 3 --max-seconds 3 \
        "${common[@]}" -o "$out/results/threads.jsonl" ;;
    summary)
      python3 - "$out" <<'PY'
import glob, json, os, sys
for path in sorted(glob.glob(os.path.join(sys.argv[1], "bench-cuda*.jsonl"))):
    print(os.path.basename(path))
    for line in open(path):
        r = json.loads(line)
        if "error" in r:
            print(f"  {r['distribution']:9} {r['side']:5}  error: {r['error']}")
            continue
        st = r.get("device_stages_ms", {})
        print(f"  {r['distribution']:9} {r['side']:5} h2h {r.get('host_to_host_ms', 0):9.1f}"
              f" reused {r.get('host_to_host_reused_ms', 0):9.1f}  gpu {r['gpu_ms']:8.2f}"
              f"  stars {st.get('stars', 0):8.2f}  backend {r['backend_ms']:8.1f}  seam {r.get('seam_share', 0):.2e}"
              f"  deferred {r['deferred']}  maxwork {r['max_cells_per_site']}")
PY
      ;;
    *) echo "run-on-device.sh: unknown step $what" >&2; exit 2 ;;
  esac
done
