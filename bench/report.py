#!/usr/bin/env python3
"""Turns expanse-bench JSON lines into docs/benchmarks.md tables and PNG plots.

    python3 bench/report.py --results bench/results --docs docs

Reads every *.jsonl under --results. For each experiment and machine it uses the latest run
(run_id) and prints, with every table, the device, date, commit and machine load it was measured
with. The method text comes from bench/benchmarks.template.md; sections without records say
"not measured yet" instead of a number.
"""
import argparse
import json
import math
import os
import re
import shutil
import statistics
import sys
from collections import defaultdict
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402  (the backend must be chosen first)

HERE = Path(__file__).resolve().parent
NOT_MEASURED = "_Not measured yet._"


def load(results_dir):
    records = []
    for path in sorted(Path(results_dir).rglob("*.jsonl")):
        for number, line in enumerate(path.read_text().splitlines(), 1):
            line = line.strip()
            if not line:
                continue
            try:
                record = json.loads(line)
            except json.JSONDecodeError as error:
                print(f"report.py: {path}:{number}: skipped ({error})", file=sys.stderr)
                continue
            record["_file"] = str(path)
            records.append(record)
    return records


def slug(text):
    return re.sub(r"[^A-Za-z0-9]+", "-", text).strip("-").lower() or "unknown"


def host(record):
    return record.get("machine", {}).get("hostname", "unknown")


def latest_runs(records, experiment):
    """The newest measurement of `experiment` per machine and configuration: {hostname: [records]}.

    An experiment may be run in parts (one distribution or backend per command on a device with a
    time limit), so each (distribution, n, implementation, layout, device) keeps its newest record
    from whichever run made it. Skip records only come from a machine's newest run, and only for
    backends with no measurement kept.
    """
    by_host = defaultdict(list)
    for r in records:
        if r.get("experiment") == experiment:
            by_host[host(r)].append(r)
    result = {}
    for hostname, rs in sorted(by_host.items()):
        newest = {}
        for r in rs:
            if r.get("skipped"):
                continue
            key = (r["distribution"], r["n"], label(r), r.get("device", ""))
            if key not in newest or r.get("run_id", "") > newest[key].get("run_id", ""):
                newest[key] = r
        kept = list(newest.values())
        measured_backends = {r["backend"] for r in kept}
        last_run = max(r.get("run_id", "") for r in rs)
        kept += [r for r in rs if r.get("skipped") and r.get("run_id", "") == last_run
                 and r["backend"] not in measured_backends]
        result[hostname] = kept
    return result


def label(r):
    """A column name: which implementation, and for GPU backends which layout."""
    if r.get("implementation") != "expanse":
        return r["backend"]
    name = f"expanse {r['backend']}"
    layout = r.get("layout")
    if layout:
        name += f" [{layout['label']}"
        if layout.get("threads_per_block"):
            name += f", T={layout['threads_per_block']}"
        name += "]"
    return name


def dist_order(key):
    """Uniform first, as in the paper, then the others by name; sizes ascending."""
    distribution, n = key
    return (distribution != "uniform", distribution, n)


def median(r):
    return r["time_ms"]["total"]["median"]


def fmt_ms(ms):
    if ms is None:
        return "—"
    if ms >= 100:
        return f"{ms:,.0f}"
    if ms >= 10:
        return f"{ms:.1f}"
    return f"{ms:.2f}"


def fmt_ratio(x):
    if x is None:
        return "—"
    return f"{x:.2f}×" if x >= 0.1 else f"{x:.2g}×"


def fmt_n(n):
    root = math.isqrt(n)
    if root * root == n and root >= 32 and (root & (root - 1)) == 0:
        return f"{root}² = {n:,}"
    return f"{n:,}"


def provenance(run):
    """One line naming where, when and on what every number of a table was measured."""
    measured = [r for r in run if not r.get("skipped")]
    if not measured:
        skipped = sorted({f"{r['backend']} ({r.get('reason', '')})" for r in run})
        return (f"{NOT_MEASURED[:-2]} on {host(run[0])} ({run[0].get('date', '')[:10]}, commit "
                f"`{run[0].get('commit', 'unknown')}`): " + "; ".join(skipped) + "._")
    first = (measured or run)[0]
    machine = first.get("machine", {})
    devices = sorted({r.get("device", "") for r in measured if r.get("implementation") == "expanse"})
    dates = sorted(r.get("date", "") for r in run)
    commits = sorted({r.get("commit", "unknown") for r in run})
    loads = [r["machine"]["load_average"][0] for r in run
             if r.get("machine", {}).get("load_average")]
    text = (f"Measured on **{machine.get('hostname', '?')}** ({machine.get('cpu', '?')}, "
            f"{machine.get('logical_cores', '?')} logical cores")
    if devices:
        text += "; Expanse devices: " + ", ".join(d for d in devices if d)
    text += f"), {dates[0][:10]} ({dates[0]} – {dates[-1]}), commit `{', '.join(commits)}`"
    if loads:
        text += f"; 1-minute load {min(loads):.1f}–{max(loads):.1f}"
    if first.get("note"):
        text += f"; note: {first['note']}"
    text += f". Warm-up {first.get('warmup', '?')}, medians of up to {max(r.get('repetitions', 0) for r in run)} repetitions."
    skipped = sorted({f"{r['backend']} ({r.get('reason', '')})" for r in run if r.get("skipped")})
    if skipped:
        text += " Skipped: " + "; ".join(skipped) + "."
    disagree = sorted({f"{label(r)} at {r['distribution']} n={r['n']}" for r in measured
                       if r.get("triangles_agree") is False})
    text += (" **Triangle counts disagree:** " + "; ".join(disagree) + "." if disagree
             else " Every implementation made the same number of triangles on the same points.")
    return text


def table(header, rows):
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(str(c) for c in row) + " |" for row in rows]
    return "\n".join(lines)


def save(fig, docs, name):
    fig.tight_layout()
    fig.savefig(docs / name, dpi=110)
    plt.close(fig)
    return name


# ---------------------------------------------------------------------------- peers


def peers_section(records, docs):
    runs = latest_runs(records, "peers")
    if not runs:
        return NOT_MEASURED
    out = []
    for hostname, run in runs.items():
        measured = [r for r in run if not r.get("skipped")]
        labels = []
        for r in measured:
            if label(r) not in labels:
                labels.append(label(r))
        cells = {(r["distribution"], r["n"], label(r)): r for r in measured}
        keys = sorted({(r["distribution"], r["n"]) for r in measured}, key=dist_order)
        out.append(f"### {hostname}\n\n{provenance(run)}\n")
        header = ["distribution", "n"] + [f"{l} ms" for l in labels] + \
                 [f"{l} / CGAL" for l in labels if l != "cgal"]
        rows = []
        for dist, n in keys:
            cgal = cells.get((dist, n, "cgal"))
            row = [dist, fmt_n(n)]
            for l in labels:
                r = cells.get((dist, n, l))
                if r:
                    t = r["time_ms"]["total"]
                    row.append(f"{fmt_ms(t['median'])} ({fmt_ms(t['min'])}–{fmt_ms(t['max'])})")
                else:
                    row.append("—")
            for l in labels:
                if l == "cgal":
                    continue
                r = cells.get((dist, n, l))
                row.append(fmt_ratio(median(r) / median(cgal)) if r and cgal else "—")
            rows.append(row)
        out.append("Times in ms: median (min–max). Ratios > 1 mean slower than CGAL.\n")
        out.append(table(header, rows))

        # Where the time goes, at the largest size: the stages each implementation reports.
        largest = max(n for _, n in keys)
        stage_rows = []
        for dist in sorted({d for d, _ in keys}, key=lambda d: dist_order((d, 0))):
            for l in labels:
                r = cells.get((dist, largest, l))
                if r and r.get("stages_ms"):
                    stages = ", ".join(f"{k} {fmt_ms(v)}" for k, v in r["stages_ms"].items())
                    device = r.get("device_stages_ms") or {}
                    if device:
                        stages += "; device: " + ", ".join(f"{k} {fmt_ms(v)}" for k, v in device.items())
                    stage_rows.append([dist, l, fmt_ms(median(r)), stages])
        if stage_rows:
            out.append(f"\nStages at n = {fmt_n(largest)} (median ms of each stage):\n")
            out.append(table(["distribution", "implementation", "total ms", "stages"], stage_rows))

        # Issue 2, item 11: the CPU backend within 2x of CGAL at 1M uniform sites.
        cpu = cells.get(("uniform", 1000000, "expanse cpu"))
        cgal = cells.get(("uniform", 1000000, "cgal"))
        if cpu and cgal:
            ratio = median(cpu) / median(cgal)
            verdict = "meets" if ratio <= 2.0 else "does **not** meet"
            fastest = cpu["time_ms"]["total"]["min"] / cgal["time_ms"]["total"]["min"]
            out.append(f"\nCPU backend vs CGAL at 1,000,000 uniform sites: {fmt_ms(median(cpu))} ms "
                       f"vs {fmt_ms(median(cgal))} ms = **{ratio:.2f}×** (medians), which {verdict} "
                       f"the ≤ 2× target of issue 2 (item 11). Fastest run against fastest run "
                       f"(the least disturbed by other jobs): {fastest:.2f}×.")

        dists = sorted({d for d, _ in keys}, key=lambda d: dist_order((d, 0)))
        fig, axes = plt.subplots(1, len(dists), figsize=(6 * len(dists), 4.5), squeeze=False)
        for ax, dist in zip(axes[0], dists):
            for l in labels:
                pts = sorted((n, median(cells[(d, n, l)])) for d, n in keys
                             if d == dist and (d, n, l) in cells)
                if pts:
                    ax.plot([p[0] for p in pts], [p[1] for p in pts], marker="o", label=l)
            ax.set_xscale("log")
            ax.set_yscale("log")
            ax.set_xlabel("points")
            ax.set_ylabel("median time (ms)")
            ax.set_title(f"{dist} — {hostname}")
            ax.grid(True, which="both", alpha=0.3)
            ax.legend(fontsize=8)
        name = save(fig, docs, f"bench-peers-{slug(hostname)}.png")
        out.append(f"\n![peers on {hostname}]({name})\n")
    return "\n".join(out)


# ---------------------------------------------------------------------------- Fig. IV.1


def threads_section(records, docs):
    runs = latest_runs(records, "threads")
    out = []
    for hostname, run in runs.items():
        measured = [r for r in run if not r.get("skipped") and r.get("layout")]
        if not measured:
            out.append(f"### {hostname}\n\n{provenance(run)}")
            continue
        out.append(f"### {hostname}\n\n{provenance(run)}\n")
        series = defaultdict(list)
        for r in measured:
            series[(r["backend"], r.get("device", ""), r["layout"]["label"])].append(r)
        rows = []
        fig, axes = plt.subplots(1, len(series), figsize=(6 * len(series), 4.5), squeeze=False)
        for ax, ((backend, device, layout), rs) in zip(axes[0], sorted(series.items())):
            by_n = defaultdict(list)
            for r in rs:
                by_n[r["n"]].append((r["layout"]["threads_per_block"], median(r)))
            for n, pts in sorted(by_n.items()):
                pts.sort()
                best_t, best = min(pts, key=lambda p: p[1])
                line, = ax.plot([p[0] for p in pts], [p[1] / best for p in pts], marker="o",
                                label=f"n = {fmt_n(n)}")
                ax.axvline(math.sqrt(n / 256), color=line.get_color(), ls=":", lw=1)
                rows.append([backend, device, layout, fmt_n(n), best_t,
                             f"{math.sqrt(n / 256):.0f}", fmt_ms(best)])
            ax.set_xscale("log", base=2)
            ax.set_xlabel("threads per block")
            ax.set_ylabel("time / best time (dotted: √(n/256))")
            ax.set_title(f"Fig. IV.1 — {backend} on {device} ({layout} layout)", fontsize=9)
            ax.grid(True, which="both", alpha=0.3)
            ax.legend(fontsize=8)
        name = save(fig, docs, f"bench-fig-iv1-{slug(hostname)}.png")
        out.append(table(["backend", "device", "layout", "n", "best T measured", "√(n/256)",
                          "best median ms"], rows))
        out.append(f"\n![Fig. IV.1 on {hostname}]({name})\n")
    return "\n".join(out) if out else NOT_MEASURED


# ---------------------------------------------------------------------------- Figs. IV.2 / IV.3


def scaling_section(records, docs, distribution, figure):
    runs = latest_runs(records, "scaling")
    out = []
    for hostname, run in runs.items():
        run = [r for r in run if r.get("distribution") == distribution]
        if not run:
            continue
        measured = [r for r in run if not r.get("skipped")]
        gpu = sorted({label(r) for r in measured
                      if r.get("implementation") == "expanse" and r["backend"] != "cpu"})
        cells = {(r["n"], label(r)): r for r in measured}
        sizes = sorted({r["n"] for r in measured})
        out.append(f"### {hostname}\n\n{provenance(run)}\n")
        header = ["n", "expanse cpu ms", "cgal ms"]
        for g in gpu:
            header += [f"{g} ms", "GPU-only ms", "vs cpu", "vs CGAL", "seam share"]
        rows = []
        for n in sizes:
            cpu, cgal = cells.get((n, "expanse cpu")), cells.get((n, "cgal"))
            row = [fmt_n(n), fmt_ms(median(cpu)) if cpu else "—", fmt_ms(median(cgal)) if cgal else "—"]
            for g in gpu:
                r = cells.get((n, g))
                if not r:
                    row += ["—"] * 5
                    continue
                device = r["time_ms"].get("device")
                row += [fmt_ms(median(r)), fmt_ms(device["median"]) if device else "—",
                        fmt_ratio(median(cpu) / median(r)) if cpu else "—",
                        fmt_ratio(median(cgal) / median(r)) if cgal else "—",
                        f"{100 * r.get('seam_share', 0):.1f}%"]
            rows.append(row)
        if not gpu:
            out.append("No GPU backend ran here, so there is no speedup to show; the CPU times "
                       "below are the baselines the GPU numbers will be divided into.\n")
            cpu_rows = [[fmt_n(n), fmt_ms(median(cells[(n, 'expanse cpu')])) if (n, 'expanse cpu') in cells else "—",
                         fmt_ms(median(cells[(n, 'cgal')])) if (n, 'cgal') in cells else "—"] for n in sizes]
            out.append(table(["n", "expanse cpu ms", "cgal ms"], cpu_rows))
            continue
        out.append("Speedup = baseline time / GPU backend time, host to host (points in, mesh out). "
                   "GPU-only: the sum of the device-timed stages.\n")
        out.append(table(header, rows))
        fig, ax = plt.subplots(figsize=(7, 4.5))
        for index, g in enumerate(gpu):
            colour = f"C{index}"  # one colour per backend and layout; dashed: over CGAL
            for base, style in (("expanse cpu", "-"), ("cgal", "--")):
                pts = [(n, median(cells[(n, base)]) / median(cells[(n, g)])) for n in sizes
                       if (n, g) in cells and (n, base) in cells]
                if pts:
                    ax.plot([p[0] for p in pts], [p[1] for p in pts], style, marker="o",
                            color=colour,
                            label=f"{g} vs {'sequential' if base == 'expanse cpu' else 'CGAL'}")
        ax.axhline(1.0, color="grey", lw=0.8)
        ax.set_xscale("log", base=2)
        ax.set_yscale("log")  # speedups below and above 1 span decades
        ax.set_xlabel("points")
        ax.set_ylabel("speedup")
        ax.set_title(f"{figure} — {distribution} — {hostname}", fontsize=9)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
        name = save(fig, docs, f"bench-{slug(figure)}-{distribution}-{slug(hostname)}.png")
        out.append(f"\n![{figure} on {hostname}]({name})\n")
    return "\n".join(out) if out else NOT_MEASURED


def iterations_section(records, docs):
    runs = latest_runs(records, "scaling")
    out = []
    for hostname, run in runs.items():
        measured = [r for r in run if not r.get("skipped") and r.get("implementation") == "expanse"
                    and r["backend"] != "cpu"]
        if not measured:
            continue
        out.append(f"### {hostname}\n\n{provenance(run)}\n")
        labels = sorted({(r["distribution"], label(r)) for r in measured})
        cells = {(r["distribution"], label(r), r["n"]): r["iterations"] for r in measured}
        sizes = sorted({r["n"] for r in measured})
        header = ["n", "log2(n/256)"] + [f"{l} ({d})" for d, l in labels]
        rows = [[fmt_n(n), f"{math.log2(n / 256):.0f}"] +
                [cells.get((d, l, n), "—") for d, l in labels] for n in sizes]
        out.append(table(header, rows))
        fig, ax = plt.subplots(figsize=(7, 4.5))
        xs = [math.log2(n / 256) for n in sizes]
        ax.plot(xs, xs, color="grey", lw=0.8, label="log2(n/256) (paper)")
        for d, l in labels:
            pts = [(math.log2(n / 256), cells[(d, l, n)]) for n in sizes if (d, l, n) in cells]
            ax.plot([p[0] for p in pts], [p[1] for p in pts], marker="o", label=f"{l} ({d})")
        ax.set_xlabel("log2(n / 256)")
        ax.set_ylabel("front iterations")
        ax.set_title(f"Iterations — {hostname}", fontsize=9)
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7)
        name = save(fig, docs, f"bench-iterations-{slug(hostname)}.png")
        out.append(f"\n![iterations on {hostname}]({name})\n")
    return "\n".join(out) if out else NOT_MEASURED


def star_work_section(records):
    """The CUDA per-site kernel's work, counted on the CPU (bench/src/star_work.cpp)."""
    by_host = defaultdict(dict)
    for r in records:
        if r.get("experiment") != "star_work":
            continue
        key = (r["distribution"], r["n"], r.get("grid", ""), r.get("search", "rings"), r.get("budget", 0))
        kept = by_host[host(r)]
        if key not in kept or r.get("run_id", "") > kept[key].get("run_id", ""):
            kept[key] = r
    out = []
    for hostname, kept in sorted(by_host.items()):
        run = sorted(kept.values(), key=lambda r: (dist_order((r["distribution"], r["n"])), r.get("grid", ""),
                                                   r.get("search", "rings")))
        first = run[0]
        machine = first.get("machine", {})
        dates = sorted(r.get("date", "") for r in run)
        commits = sorted({r.get("commit", "unknown") for r in run})
        out.append(f"### {hostname}\n\nCounted on **{hostname}** ({machine.get('cpu', '?')}), "
                   f"{dates[0][:10]}, commit `{', '.join(commits)}`. Counts, not times: they do "
                   f"not depend on the machine or its load.\n")
        rows = []
        for r in run:
            reasons = [f"{r[k]} {name}" for k, name in (("deferred_undecided", "undecided/budget"),
                                                          ("deferred_full_row", "full row"),
                                                          ("deferred_no_apex", "no apex")) if r.get(k)]
            share = r["deferred"] / r["sites"] if r["sites"] else 0.0
            # Records from before the box scans (star_scan.cuh) have no "search": they are rings.
            # Lane shares came with session 4's records; older ones have none.
            lanes = (f"{r['lane_share_8']:.2f} / {r['lane_share_32']:.2f}" if "lane_share_8" in r else "–")
            rows.append([r["distribution"], fmt_n(r["n"]), r.get("grid", ""), r.get("search", "rings"),
                         f"{r.get('budget', 0):,}", f"{r['predicates_per_site']:.1f}",
                         f"{r['work_per_site']:.1f}", f"{r['max_work']:,}", f"{r['sites_over_4096']:,}",
                         f"{r['deferred']:,} ({share:.3%})" + (f": {', '.join(reasons)}" if reasons else ""),
                         lanes])
        out.append(table(["distribution", "n", "grid", "search", "budget", "predicates / site",
                          "cells + sites / site", "max one site", "sites > 4096", "sites deferred",
                          "lane share 8 / 32"], rows))
    return "\n".join(out) if out else NOT_MEASURED


def picture_file(r):
    """The picture a record names, also when its results folder was made on another machine
    and copied here (the record holds that machine's absolute path)."""
    if not r.get("picture"):
        return None
    for candidate in (Path(r["picture"]), Path(r["_file"]).parent / "pictures" / Path(r["picture"]).name):
        if candidate.exists():
            return candidate
    return None


def pictures_section(records, docs):
    runs = latest_runs(records, "pictures")
    out = []
    for hostname, run in runs.items():
        pictured = [r for r in run if picture_file(r)]
        if not pictured:
            continue
        out.append(f"### {hostname}\n\n{provenance(run)}\n")
        rows = []
        for r in sorted(pictured, key=lambda r: (dist_order((r["distribution"], r["n"])), label(r))):
            name = f"bench-{slug(hostname)}-{Path(r['picture']).name}"
            shutil.copyfile(picture_file(r), docs / name)
            note = r.get("picture_note", "unfilled: GPU front growth; filled orange: CPU seam stage")
            rows.append([r["distribution"], fmt_n(r["n"]), label(r),
                         f"{100 * r.get('seam_share', 0):.1f}%", note, f"![]({name})"])
        out.append(table(["distribution", "n", "backend", "seam share", "colours", "picture"], rows))
    return "\n".join(out) if out else NOT_MEASURED


# The targets issue 5 asks for; each is either backed by records or says it is not measured.
TARGETS = [
    ("CUDA (H100 wanted)", lambda r: r["backend"] == "cuda"),
    ("Vulkan on an NVIDIA GPU (H100 wanted)",
     lambda r: r["backend"] == "vulkan" and "llvmpipe" not in r.get("device", "")),
    ("Vulkan on lavapipe (llvmpipe)", lambda r: r["backend"] == "vulkan" and "llvmpipe" in r.get("device", "")),
    ("CPU backend and peers", lambda r: r["backend"] in ("cpu", "cgal", "qhull", "delaunator")),
]


def status_section(records):
    # Only the records the sections below show (newest per configuration), so the commits listed
    # here are the ones the numbers come from.
    shown = []
    for experiment in sorted({r.get("experiment", "") for r in records}):
        for kept in latest_runs(records, experiment).values():
            shown += kept
    measured = [r for r in shown if not r.get("skipped")]
    rows = []
    for name, matches in TARGETS:
        hits = [r for r in measured if matches(r)]
        if not hits:
            rows.append([name, "—", "—", "not measured yet", "—", "—"])
            continue
        experiments = sorted({r["experiment"] for r in hits})
        hosts = sorted({host(r) for r in hits})
        dates = sorted(r.get("date", "")[:10] for r in hits)
        commits = sorted({r.get("commit", "unknown") for r in hits})
        devices = sorted({r.get("device", "") for r in hits})
        rows.append([name, ", ".join(hosts), ", ".join(devices), ", ".join(experiments),
                     dates[0] if dates[0] == dates[-1] else f"{dates[0]} – {dates[-1]}",
                     ", ".join(f"`{c}`" for c in commits)])
    return table(["target", "machine", "devices", "experiments measured", "date", "commit"], rows)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--results", default=str(HERE / "results"))
    parser.add_argument("--docs", default=str(HERE.parent / "docs"))
    parser.add_argument("--template", default=str(HERE / "benchmarks.template.md"))
    args = parser.parse_args()

    docs = Path(args.docs)
    docs.mkdir(parents=True, exist_ok=True)
    records = load(args.results)
    sections = {
        "STATUS": status_section(records),
        "PEERS": peers_section(records, docs),
        "FIG_IV1": threads_section(records, docs),
        "FIG_IV2": scaling_section(records, docs, "uniform", "Fig. IV.2"),
        "FIG_IV3": scaling_section(records, docs, "gaussian", "Fig. IV.3"),
        "ITERATIONS": iterations_section(records, docs),
        "PICTURES": pictures_section(records, docs),
        "STAR_WORK": star_work_section(records),
    }
    text = Path(args.template).read_text()
    for key, body in sections.items():
        text = text.replace("{{" + key + "}}", body)
    (docs / "benchmarks.md").write_text(text)
    print(f"report.py: {len(records)} records -> {docs / 'benchmarks.md'}", file=sys.stderr)


if __name__ == "__main__":
    main()
