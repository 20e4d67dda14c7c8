#!/usr/bin/env python3
"""Summarises an ncu source-counters CSV (callN-ncu-sass.csv.xz): warp instructions, active lanes,
stall reasons, instruction mix, and the candidate loop's hottest FP64 instruction.

    python3 ncu-summary.py call4-ncu-sass.csv.xz [call5-ncu-sass.csv.xz]
"""
import collections
import csv
import io
import lzma
import re
import sys


def rows_of(path):
    text = lzma.open(path, "rt").read() if path.endswith(".xz") else open(path).read()
    lines = text.split("\n")
    start = next(i for i, line in enumerate(lines) if line.startswith('"Address"'))
    rows = list(csv.reader(io.StringIO("\n".join(lines[start:]))))
    header = rows[0]
    return header, [r for r in rows[1:] if len(r) == len(header)]


def summarise(path):
    header, data = rows_of(path)
    col = {h: i for i, h in enumerate(header)}

    def value(row, key):
        try:
            return float(row[col[key]])
        except ValueError:
            return 0.0

    executed = [value(r, "Instructions Executed") for r in data]
    lanes = [value(r, "Thread Instructions Executed") for r in data]
    samples = [value(r, "Warp Stall Sampling (All Samples)") for r in data]
    total, total_samples = sum(executed), sum(samples)
    print(f"{path}: {total / 1e9:.2f} G warp instructions, {sum(lanes) / total:.1f} active lanes, "
          f"{total_samples / 1e6:.2f} M stall samples")
    reasons = [h for h in header if h.startswith("stall_") and "Not Issued" not in h]
    shares = sorted(((sum(value(r, k) for r in data), k) for k in reasons), reverse=True)[:6]
    print("  stalls: " + ", ".join(f"{k[6:]} {100 * v / total_samples:.1f}%" for v, k in shares))
    mix = collections.Counter()
    for row, count in zip(data, executed):
        match = re.match(r"(@!?U?P\w+\s+)?([A-Z0-9_]+)", row[col["Source"]].strip())
        mix[match.group(2) if match else "?"] += count
    print("  mix: " + ", ".join(f"{op} {count / 1e9:.2f} G" for op, count in mix.most_common(12)))
    fp64 = [i for i, r in enumerate(data) if re.search(r"\bD(ADD|MUL|FMA|SETP)\b", r[col["Source"]])]
    print(f"  FP64: {100 * sum(executed[i] for i in fp64) / total:.0f}% of warp instructions")
    hottest = max(fp64, key=lambda i: executed[i])
    print(f"  hottest FP64 instruction: {executed[hottest] / 1e6:.1f} M times at {lanes[hottest] / executed[hottest]:.1f} lanes")
    worst = max(range(len(data)), key=lambda i: samples[i])
    print(f"  most stall samples: {100 * samples[worst] / total_samples:.1f}% at `{data[worst][col['Source']].strip()}`")


for argument in sys.argv[1:]:
    summarise(argument)
