#!/usr/bin/env python3
"""Writes docs/benchmarks.md and its plots from the data set in bench/data/.

    python3 bench/report.py                        # bench/data -> docs/benchmarks.md, docs/bench-*.png
    python3 bench/report.py --merge DIR [DIR ...]  # first fold a run's JSON lines into bench/data
    python3 bench/report.py --data DIR --docs OUT  # any folder of records (bench/run.sh --quick)

bench/data holds one JSONL file per experiment: for each configuration (machine or device,
implementation, layout, input, size) the newest measurement. --merge replaces the rows of every
configuration a new run measured and keeps the rest. Every row carries its device, date, commit,
command and host CPU; the page is the template bench/benchmarks.template.md with its {{KEYS}}
replaced by tables and plots. A section without rows says "not measured".
"""
import argparse
import datetime
import json
import math
import re
import sys
from collections import defaultdict
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402  (the backend must be chosen first)

HERE = Path(__file__).resolve().parent
NOT_MEASURED = "_Not measured._"

# ---------------------------------------------------------------------------- records


def experiment_of(r):
    """The data file a record belongs in; the stage programs write no "experiment" field."""
    if r.get("experiment"):
        return r["experiment"]
    if "side" in r:
        return "cuda_pipeline"
    if "transfer" in r:
        return "cuda_transfers"
    if r.get("benchmark") == "page_faults":
        return "page_faults"
    if "stages" in r and "total_ms" in r:
        return "bench_vulkan"
    return "other"


def host(r):
    return r.get("machine", {}).get("hostname", "unknown")


def layout_of(r):
    layout = r.get("layout")
    return layout if isinstance(layout, dict) else {"label": layout}


def config_key(r):
    """What a measurement is of: a newer row with the same key replaces an older one."""
    experiment = experiment_of(r)
    if experiment == "cuda_pipeline":
        return (r.get("device"), r.get("layout"), r["distribution"], r["side"], r.get("scale", 1))
    if experiment == "cuda_transfers":
        return (r.get("device"), r["transfer"])
    if experiment == "page_faults":
        return (r.get("device"), r["variant"], r["threads"], r["huge_pages"])
    if experiment == "host_stages":
        return (host(r), r["stage"], r["distribution"], r["n"], r["threads"])
    if experiment == "star_work":
        return (r["distribution"], r["n"], r.get("grid", ""), r.get("search", "rings"), r.get("budget", 0))
    if experiment == "bench_vulkan":
        return (r.get("device"), r["n"], r.get("distribution"), r.get("layout"), r.get("blocks"),
                r.get("buckets"), r.get("threads"))
    layout = layout_of(r)
    return (host(r), r.get("backend"), r.get("device"), layout.get("label"),
            layout.get("threads_per_block"), r.get("distribution"), r.get("n"))


def read_jsonl(path):
    rows = []
    for number, line in enumerate(Path(path).read_text().splitlines(), 1):
        if not line.strip():
            continue
        try:
            rows.append(json.loads(line))
        except json.JSONDecodeError as error:
            print(f"report.py: {path}:{number}: skipped ({error})", file=sys.stderr)
    return rows


def load(data_dir):
    records = defaultdict(list)
    for path in sorted(Path(data_dir).rglob("*.jsonl")):
        for r in read_jsonl(path):
            if not r.get("skipped"):
                records[experiment_of(r)].append(r)
    return records


def merge(data_dir, run_dirs, defaults):
    """Folds the JSON lines under run_dirs into data_dir, one file per experiment: every
    configuration the run measured loses its old rows and takes the run's (all its rounds)."""
    new = defaultdict(list)
    for run_dir in run_dirs:
        for path in sorted(Path(run_dir).rglob("*.jsonl")):
            for r in read_jsonl(path):
                if r.get("skipped"):
                    continue
                for field, value in defaults.items():
                    if not r.get(field):
                        r[field] = value
                r.setdefault("cpu", r.get("machine", {}).get("cpu", "unknown"))
                r["experiment"] = experiment_of(r)
                if r["experiment"] != "pictures":  # they name files in the run's folder
                    new[r["experiment"]].append(r)
    Path(data_dir).mkdir(parents=True, exist_ok=True)
    for experiment, rows in sorted(new.items()):
        path = Path(data_dir) / f"{experiment}.jsonl"
        old = read_jsonl(path) if path.exists() else []
        measured = {config_key(r) for r in rows}
        kept = [r for r in old if config_key(r) not in measured] + rows
        path.write_text("".join(json.dumps(r, separators=(",", ":")) + "\n" for r in kept))
        print(f"report.py: {path}: {len(rows)} new rows, {len(kept)} in all", file=sys.stderr)


# ---------------------------------------------------------------------------- formatting


def fmt_ms(ms):
    if ms is None:
        return "—"
    if ms >= 100:
        return f"{ms:,.0f}"
    if ms >= 10:
        return f"{ms:.1f}"
    return f"{ms:.2f}"


def fmt_n(n):
    root = math.isqrt(n)
    if root * root == n and root >= 32 and (root & (root - 1)) == 0:
        return f"{root}²"
    return f"{n:,}"


def fmt_share(x):
    return "0" if not x else f"{100 * x:.2g}%"


def short(commit):
    commit = str(commit or "unknown")
    return commit if commit == "unknown" else re.sub(r"^([0-9a-f]{7})[0-9a-f]*", r"\1", commit)


def day(r):
    return str(r.get("date", "unknown"))[:10]


def median(r):
    return r["time_ms"]["total"]["median"]


def table(header, rows):
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(str(c) for c in row) + " |" for row in rows]
    return "\n".join(lines)


def label(r):
    """An implementation's name: Expanse's backend and layout, or the peer."""
    if r.get("implementation") != "expanse":
        return r["backend"]
    layout = layout_of(r).get("label")
    return f"{r['backend']} [{layout}]" if layout else r["backend"]


def provenance(rows, what):
    """Where, when, on what and by which command the rows of a table were measured."""
    groups = defaultdict(set)
    for r in rows:
        # One line for the rows a command made with one size or input each.
        command = re.sub(r"( -n| --n| --dist| --threads) [^\s,]+(?=\s|$)", "", r.get("command", "unknown"))
        groups[(what(r), r.get("device", "unknown"), r.get("cpu", "unknown"), day(r), short(r.get("commit")))].add(command)
    lines = []
    for (name, device, cpu, date, commit), commands in sorted(groups.items()):
        line = f"- {name}: {device}"
        if cpu and cpu not in device:
            line += f", host CPU {cpu}"
        line += f"; {date}, commit `{commit}`; " + "; ".join(f"`{c}`" for c in sorted(commands))
        lines.append(line)
    return "\n".join(lines)


def style(ax, xlabel, ylabel, title, xscale=None, yscale=None):
    """The axes every plot shares: labels, title, grid, a small legend; log scales where asked."""
    if xscale:
        ax.set_xscale("log", base=xscale)
    if yscale:
        ax.set_yscale("log")
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title(title, fontsize=8)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=6)


def save(fig, docs, name):
    fig.tight_layout()
    fig.savefig(docs / name, dpi=72)
    plt.close(fig)
    return name


# ---------------------------------------------------------------------------- CUDA pipeline


def gpu_only(r):
    """The pipeline's device stages without the transfers (the device's own preparation included)."""
    stages = r.get("pipeline_device_stages_ms") or r.get("device_stages_ms") or {}
    return sum(v for k, v in stages.items() if k not in ("upload", "download"))


def cuda_section(records):
    rows = records.get("cuda_pipeline", [])
    if not rows:
        return NOT_MEASURED
    cells = defaultdict(list)
    for r in rows:
        cells[(r["device"], r["distribution"], r["side"])].append(r)
    order = {"uniform": 0, "gaussian": 1, "grid": 2, "kuzmin": 3}
    out = []
    for (device, dist, side), rs in sorted(cells.items(), key=lambda kv: (kv[0][0], kv[0][2], order.get(kv[0][1], 9))):
        rs.sort(key=lambda r: r.get("round", 1))
        joined = lambda f: " / ".join(fmt_ms(f(r)) for r in rs)  # noqa: E731
        out.append([device, dist, fmt_n(side * side), joined(lambda r: r.get("host_to_host_ms")),
                    joined(lambda r: r.get("host_to_host_reused_ms")), joined(gpu_only),
                    joined(lambda r: (r.get("pipeline_device_stages_ms") or {}).get("stars")),
                    f"{rs[-1]['deferred']:,}", fmt_share(rs[-1].get("seam_share"))])
    text = ("Each cell lists every round of the run (medians of `--reps` repetitions after a warm-up).\n\n"
            + table(["device", "input", "n", "host to host ms", "into a kept mesh ms", "GPU-only ms",
                     "stars ms", "sites deferred", "seam share"], out))
    return text + "\n\n" + provenance(rows, lambda r: "expanse_bench_cuda")


def cuda_transfers_section(records):
    rows = records.get("cuda_transfers", [])
    if not rows:
        return NOT_MEASURED
    out = [[r["transfer"], f"{r.get('bytes', 0) / 1e6:,.0f}" if r.get("bytes") else "—",
            fmt_ms(r["median_ms"]), f"{r['gb_per_s']:.1f}" if r.get("gb_per_s") else "—"] for r in rows]
    return table(["transfer", "MB", "median ms", "GB/s"], out) + "\n\n" + provenance(rows, lambda r: "transfers")


# ---------------------------------------------------------------------------- expanse-bench experiments


def dist_order(dist):
    return (dist != "uniform", dist)


def scaling_section(records, docs):
    rows = [r for r in records.get("scaling", []) if r.get("time_ms")]
    if not rows:
        return NOT_MEASURED
    labels = sorted({label(r) for r in rows}, key=lambda l: (l not in ("cpu", "cgal"), l))
    cells = {(host(r), r["distribution"], r["n"], label(r)): r for r in rows}
    keys = sorted({(host(r), r["distribution"], r["n"]) for r in rows},
                  key=lambda k: (k[0], dist_order(k[1]), k[2]))
    out = []
    for h, dist, n in keys:
        row = [h, dist, fmt_n(n)]
        for l in labels:
            r = cells.get((h, dist, n, l))
            row.append(fmt_ms(median(r)) if r else "—")
        out.append(row)
    text = ("Host to host (points in, mesh with neighbours out), median ms.\n\n"
            + table(["machine", "input", "n"] + [f"{l} ms" for l in labels], out))

    # Figs. IV.2 and IV.3: speedup of each GPU backend over CGAL on the same machine and points.
    dists = sorted({r["distribution"] for r in rows}, key=dist_order)
    fig, axes = plt.subplots(1, len(dists), figsize=(5 * len(dists), 3.4), squeeze=False)
    for ax, dist in zip(axes[0], dists):
        for h in sorted({k[0] for k in keys}):
            for l in labels:
                if l in ("cpu", "cgal"):
                    continue
                pts = [(n, median(cells[(h, dist, n, "cgal")]) / median(cells[(h, dist, n, l)]))
                       for hh, d, n in keys if hh == h and d == dist
                       and (h, dist, n, l) in cells and (h, dist, n, "cgal") in cells]
                if pts:
                    ax.plot([p[0] for p in pts], [p[1] for p in pts], marker="o", ms=3, label=f"{l}, {h}")
        ax.axhline(1.0, color="grey", lw=0.8)
        style(ax, "points", "speedup over CGAL", f"{'Fig. IV.2' if dist == 'uniform' else 'Fig. IV.3'}: {dist}",
              xscale=2, yscale=True)
    name = save(fig, docs, "bench-speedup.png")
    text += f"\n\n![speedup over CGAL]({name})\n\n" + provenance(rows, label)
    return text


def iterations_section(records, docs):
    rows = [r for r in records.get("scaling", []) if r.get("implementation") == "expanse"
            and r["backend"] != "cpu" and r.get("iterations") is not None]
    if not rows:
        return NOT_MEASURED
    series = defaultdict(dict)
    for r in rows:
        series[(host(r), label(r), r["distribution"])][r["n"]] = r["iterations"]
    sizes = sorted({r["n"] for r in rows})
    out = [[h, l, d] + [s.get(n, "—") for n in sizes] for (h, l, d), s in sorted(series.items())]
    fig, ax = plt.subplots(figsize=(6, 3.4))
    xs = [math.log2(n / 256) for n in sizes if n >= 256]
    ax.plot(xs, xs, color="grey", lw=0.8, label="log2(n/256) (paper)")
    for (h, l, d), s in sorted(series.items()):
        if "paper" in l:
            pts = sorted((math.log2(n / 256), it) for n, it in s.items() if n >= 256)
            ax.plot([p[0] for p in pts], [p[1] for p in pts], marker="o", ms=3, label=f"{l}, {d}, {h}")
    style(ax, "log2(n / 256)", "front iterations", "front iterations, paper layout")
    name = save(fig, docs, "bench-iterations.png")
    return (table(["machine", "implementation", "input"] + [fmt_n(n) for n in sizes], out)
            + f"\n\n![iterations]({name})\n\nThe same runs as the scaling table.")


def threads_section(records, docs):
    rows = [r for r in records.get("threads", []) if r.get("time_ms")]
    if not rows:
        return NOT_MEASURED
    series = defaultdict(lambda: defaultdict(list))
    for r in rows:
        series[(host(r), r["backend"], r.get("device", ""))][r["n"]].append(
            (layout_of(r).get("threads_per_block"), median(r)))
    out = []
    fig, axes = plt.subplots(1, len(series), figsize=(4 * len(series), 3.2), squeeze=False)
    for ax, ((h, backend, device), by_n) in zip(axes[0], sorted(series.items())):
        for n, pts in sorted(by_n.items()):
            pts.sort()
            best_t, best = min(pts, key=lambda p: p[1])
            out.append([h, backend, device, fmt_n(n), best_t, f"{math.sqrt(n / 256):.0f}", fmt_ms(best)])
            line, = ax.plot([p[0] for p in pts], [p[1] / best for p in pts], marker="o", ms=3, label=fmt_n(n))
            ax.axvline(math.sqrt(n / 256), color=line.get_color(), ls=":", lw=1)
        style(ax, "threads per block", "time / best (dotted: √(n/256))", f"{backend}, {device}", xscale=2)
    name = save(fig, docs, "bench-threads.png")
    return (table(["machine", "backend", "device", "n", "best threads per block", "√(n/256)", "best ms"], out)
            + f"\n\n![Fig. IV.1]({name})\n\n" + provenance(rows, lambda r: r["backend"]))


def peers_section(records, docs):
    rows = [r for r in records.get("peers", []) if r.get("time_ms")]
    if not rows:
        return NOT_MEASURED
    labels = sorted({label(r) for r in rows}, key=lambda l: (l != "cgal", l))
    cells = {(host(r), r["distribution"], r["n"], label(r)): r for r in rows}
    keys = sorted({(host(r), r["distribution"], r["n"]) for r in rows}, key=lambda k: (k[0], dist_order(k[1]), k[2]))
    out = []
    for h, dist, n in keys:
        cgal = cells.get((h, dist, n, "cgal"))
        row = [h, dist, fmt_n(n)]
        for l in labels:
            r = cells.get((h, dist, n, l))
            ratio = f" ({median(r) / median(cgal):.2f}×)" if r and cgal and l != "cgal" else ""
            row.append(fmt_ms(median(r)) + ratio if r else "—")
        out.append(row)
    dists = sorted({k[1] for k in keys}, key=dist_order)
    fig, axes = plt.subplots(1, len(dists), figsize=(5 * len(dists), 3.4), squeeze=False)
    for ax, dist in zip(axes[0], dists):
        for l in labels:
            pts = sorted((n, median(cells[(h, d, n, l)])) for h, d, n in keys if d == dist and (h, d, n, l) in cells)
            if pts:
                ax.plot([p[0] for p in pts], [p[1] for p in pts], marker="o", ms=3, label=l)
        style(ax, "points", "median ms", dist, xscale=10, yscale=True)
    name = save(fig, docs, "bench-peers.png")
    return ("Median ms, in brackets the ratio to CGAL on the same points (> 1: slower than CGAL).\n\n"
            + table(["machine", "input", "n"] + [f"{l}" for l in labels], out)
            + f"\n\n![peers]({name})\n\n" + provenance(rows, label))


def lavapipe_section(records):
    rows = [r for r in records.get("lavapipe_1m", []) if r.get("time_ms")]
    if not rows:
        return NOT_MEASURED
    runs = defaultdict(dict)
    for r in rows:
        runs[(day(r), short(r["commit"]), r["distribution"], r.get("note", ""))][r["backend"]] = r
    out = []
    for (date, commit, dist, note), by in sorted(runs.items()):
        v, c = by.get("vulkan"), by.get("cgal")
        out.append([date, f"`{commit}`", dist, note or "—", fmt_ms(median(v)) if v else "—",
                    fmt_ms(median(c)) if c else "not run", f"{median(v) / median(c):.2f}×" if v and c else "—",
                    fmt_share(v.get("seam_share")) if v else "—"])
    return (table(["date", "commit", "input", "round", "lavapipe ms", "CGAL ms (same round)", "ratio",
                   "seam share"], out) + "\n\n" + provenance(rows, lambda r: r["backend"]))


def star_work_section(records):
    rows = records.get("star_work", [])
    if not rows:
        return NOT_MEASURED
    out = []
    for r in sorted(rows, key=lambda r: (dist_order(r["distribution"]), r["n"], r.get("grid", ""),
                                         r.get("search", "rings"), r.get("budget", 0))):
        share = r["deferred"] / r["sites"] if r.get("sites") else 0.0
        out.append([r["distribution"], fmt_n(r["n"]), r.get("grid", ""), r.get("search", "rings"),
                    f"{r.get('budget', 0):,}", f"{r['predicates_per_site']:.1f}", f"{r['work_per_site']:.1f}",
                    f"{r['max_work']:,}", f"{r['deferred']:,} ({share:.3%})"])
    return ("Counts, not times: they do not depend on the machine or its load.\n\n"
            + table(["input", "n", "grid", "search", "budget", "predicates / site", "cells + sites / site",
                     "max one site", "sites deferred"], out)
            + "\n\n" + provenance(rows, lambda r: "expanse-bench-star-work"))


def host_stages_section(records):
    rows = records.get("host_stages", [])
    if not rows:
        return NOT_MEASURED
    out = [[r["stage"], r["distribution"], fmt_n(r["n"]), r["threads"], fmt_ms(r["median_ms"]),
            f"{fmt_ms(r['min_ms'])}–{fmt_ms(r['max_ms'])}"] for r in rows]
    return (table(["stage", "input", "n", "threads", "median ms", "min–max"], out)
            + "\n\n" + provenance(rows, lambda r: "expanse-bench-host-stages"))


def page_faults_section(records):
    rows = records.get("page_faults", [])
    if not rows:
        return NOT_MEASURED
    huge = {-1: "—", 0: "no", 1: "yes"}
    out = [[r["variant"], r["threads"], huge.get(r["huge_pages"], r["huge_pages"]), fmt_ms(r["median_ms"]),
            f"{r['gb_per_s']:.1f}"] for r in sorted(rows, key=lambda r: (r["variant"], r["huge_pages"], r["threads"]))]
    return (f"{rows[0].get('mib', '?')} MiB of fresh storage.\n\n"
            + table(["variant", "threads", "huge pages", "median ms", "GB/s"], out)
            + "\n\n" + provenance(rows, lambda r: "expanse-bench-page-faults"))


def bench_vulkan_section(records):
    rows = [r for r in records.get("bench_vulkan", [])]
    if not rows:
        return NOT_MEASURED
    out = [[f"{r['n']:,}", r["distribution"], r.get("layout"), r.get("blocks") or "default",
            r.get("threads") or "default", fmt_ms(r["total_ms"]),
            fmt_ms((r.get("device_stages") or {}).get("vulkan: stars")), fmt_share(r.get("seam_share"))]
           for r in rows]
    return ("The second run of each configuration (the first pays device start-up).\n\n"
            + table(["n", "input", "layout", "blocks a side", "threads per block", "total ms", "star shader ms",
                     "seam share"], out)
            + "\n\n" + provenance(rows, lambda r: "expanse_vulkan_bench"))


# ---------------------------------------------------------------------------- targets


def verdict(ok):
    return "met" if ok else "**not met**"


def targets_section(records):
    """The issues' targets against the data set's current numbers."""
    out = []
    peers = {(host(r), r["distribution"], r["n"], label(r)): r for r in records.get("peers", []) if r.get("time_ms")}
    for (h, dist, n, l), cpu in sorted(peers.items()):
        cgal = peers.get((h, dist, n, "cgal"))
        if l == "cpu" and dist == "uniform" and n == 1000000 and cgal:
            ratio = median(cpu) / median(cgal)
            out.append(["CPU backend vs CGAL, 10⁶ uniform (issue 2)", "≤ 2×",
                        f"{fmt_ms(median(cpu))} vs {fmt_ms(median(cgal))} ms = {ratio:.2f}× ({cpu.get('cpu')}, {day(cpu)})",
                        verdict(ratio <= 2)])

    cuda = defaultdict(list)
    for r in records.get("cuda_pipeline", []):
        if "H100" in r.get("device", ""):
            cuda[(r["distribution"], r["side"])].append(r)
    if cuda:
        any_row = next(iter(cuda.values()))[0]
        where = f"H100, {day(any_row)}, `{short(any_row.get('commit'))}`"
        uniform = cuda.get(("uniform", 4096), [])
        if uniform:
            h2h = [r["host_to_host_ms"] for r in uniform]
            out.append(["CUDA 4096² uniform, host to host (issue 4)", "≤ 170 ms",
                        " / ".join(fmt_ms(x) for x in h2h) + f" ms ({where})", verdict(max(h2h) <= 170)])
            g = [gpu_only(r) for r in uniform]
            out.append(["CUDA 4096² uniform, GPU-only (issue 4)", "≤ 30 ms",
                        " / ".join(f"{x:.2f}" for x in g) + f" ms ({where})", verdict(max(g) <= 30)])
            for measure, name in ((lambda r: r["host_to_host_ms"], "host to host"), (gpu_only, "GPU-only")):
                ratios = []
                for dist in ("gaussian", "grid", "kuzmin"):
                    rs = cuda.get((dist, 4096), [])
                    if rs:
                        ratios.append((dist, [measure(a) / measure(b) for a, b in zip(rs, uniform)]))
                if ratios:
                    worst = max(max(v) for _, v in ratios)
                    out.append([f"CUDA gaussian / grid / kuzmin against uniform at 4096², {name} (issue 4)", "≤ 1.5×",
                                "; ".join(f"{d} " + " / ".join(f"{x:.3f}×" for x in v) for d, v in ratios) + f" ({where})",
                                verdict(worst <= 1.5)])
        small = cuda.get(("uniform", 512), [])
        if small:
            g = [gpu_only(r) for r in small]
            out.append(["CUDA 512² uniform, GPU-only (issue 4)", "≤ 4 ms", " / ".join(f"{x:.2f}" for x in g) + f" ms ({where})",
                        verdict(max(g) <= 4)])
        shares = [r.get("seam_share", 0) for rs in cuda.values() for r in rs]
        out.append(["CUDA seam share, every input and size measured (issue 4)", "≤ 0.1%",
                    f"at most {fmt_share(max(shares))} ({where})", verdict(max(shares) <= 0.001)])

    scaling = [r for r in records.get("scaling", []) if r.get("time_ms")]
    vk = [r for r in scaling if r["backend"] == "vulkan" and layout_of(r).get("label") == "default"
          and r["n"] == 1024 * 1024 and "H100" in r.get("device", "")]
    if vk:
        shares = ", ".join(f"{r['distribution']} {fmt_share(r.get('seam_share'))}" for r in sorted(vk, key=lambda r: dist_order(r["distribution"])))
        out.append(["Vulkan seam share, 1024² uniform / gaussian (issue 3)", "< 1%",
                    f"{shares} (H100, {day(vk[0])}, `{short(vk[0]['commit'])}`)",
                    verdict(max(r.get("seam_share", 0) for r in vk) < 0.01)])
    lava = defaultdict(dict)
    for r in records.get("lavapipe_1m", []):
        if r["distribution"] == "uniform" and r.get("time_ms"):
            lava[(r["run_id"][:16], r.get("note", ""), day(r), short(r["commit"]))][r["backend"]] = r
    paired = [(k, v) for k, v in sorted(lava.items()) if "vulkan" in v and "cgal" in v]
    if paired:
        ratios = [median(v["vulkan"]) / median(v["cgal"]) for _, v in paired]
        k = paired[-1][0]
        out.append(["Vulkan on lavapipe, 10⁶ uniform (issue 3)", "< CGAL",
                    " / ".join(f"{x:.2f}×" for x in ratios) + f" of CGAL, rounds alternated in one run "
                    f"({paired[-1][1]['vulkan'].get('cpu')}, {k[2]}, `{k[3]}`)", verdict(max(ratios) < 1)])
    pair = {(r["backend"]): r for r in scaling if host(r) == "h100-host" and r["distribution"] == "uniform"
            and r["n"] == 4096 * 4096 and layout_of(r).get("label") == "default"}
    if "vulkan" in pair and "cuda" in pair:
        ratio = median(pair["vulkan"]) / median(pair["cuda"])
        out.append(["Vulkan vs CUDA on the H100, 4096² uniform, host to host (issue 3)", "≤ 1.5×",
                    f"{fmt_ms(median(pair['vulkan']))} vs {fmt_ms(median(pair['cuda']))} ms = {ratio:.2f}× "
                    f"({day(pair['vulkan'])}, `{short(pair['vulkan']['commit'])}`)", verdict(ratio <= 1.5)])
    return table(["target", "goal", "current numbers", "status"], out) if out else NOT_MEASURED


# ---------------------------------------------------------------------------- main


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--data", default=str(HERE / "data"), help="folder of *.jsonl records")
    parser.add_argument("--docs", default=str(HERE.parent / "docs"))
    parser.add_argument("--template", default=str(HERE / "benchmarks.template.md"))
    parser.add_argument("--merge", nargs="+", metavar="RUN_DIR", help="fold these runs into --data first")
    parser.add_argument("--commit", default="unknown", help="--merge: commit for records without one")
    parser.add_argument("--date", default=datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d"),
                        help="--merge: date for records without one")
    parser.add_argument("--device", default="unknown", help="--merge: device for records without one")
    parser.add_argument("--command", default="unknown", help="--merge: command for records without one")
    parser.add_argument("--no-docs", action="store_true", help="--merge only")
    args = parser.parse_args()

    if args.merge:
        merge(args.data, args.merge, {"commit": args.commit, "date": args.date, "device": args.device,
                                      "command": args.command})
        if args.no_docs:
            return
    docs = Path(args.docs)
    docs.mkdir(parents=True, exist_ok=True)
    records = load(args.data)
    sections = {
        "TARGETS": targets_section(records),
        "CUDA_PIPELINE": cuda_section(records),
        "SCALING": scaling_section(records, docs),
        "ITERATIONS": iterations_section(records, docs),
        "THREADS": threads_section(records, docs),
        "PEERS": peers_section(records, docs),
        "LAVAPIPE": lavapipe_section(records),
        "STAR_WORK": star_work_section(records),
        "HOST_STAGES": host_stages_section(records),
        "PAGE_FAULTS": page_faults_section(records),
        "TRANSFERS": cuda_transfers_section(records),
        "BENCH_VULKAN": bench_vulkan_section(records),
    }
    text = Path(args.template).read_text()
    for key, body in sections.items():
        text = text.replace("{{" + key + "}}", body)
    (docs / "benchmarks.md").write_text(text)
    count = sum(len(v) for v in records.values())
    print(f"report.py: {count} records -> {docs / 'benchmarks.md'}", file=sys.stderr)


if __name__ == "__main__":
    main()
