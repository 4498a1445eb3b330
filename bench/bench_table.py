#!/usr/bin/env python3
"""Markdown tables from a Google Benchmark JSON file of hs_bench_stepper.

usage: hs_bench_stepper --benchmark_out=bench.json --benchmark_out_format=json
       python3 -m bench.bench_table bench.json
Prints particle-steps per CPU second for the scaling (N x phi), one-box, cells sweep and
kernel-specialisation families.
"""
import json
import re
import sys
from collections import defaultdict


def parse(name):
    family = name.split("/")[0]
    args = dict(re.findall(r"([A-Za-z%]+):(\d+)", name))
    return family, args


def rate(b):
    return b["particle_steps_per_s"] / 1e6


def main(path):
    rows = [b for b in json.load(open(path))["benchmarks"] if b.get("run_type", "iteration") == "iteration"]
    fam = defaultdict(list)
    for b in rows:
        f, a = parse(b["name"])
        fam[f].append((a, b))

    if fam["Scaling"] or fam["OneBox"]:
        table = defaultdict(dict)
        for f in ("Scaling", "OneBox"):
            for a, b in fam[f]:
                table[(int(a["N"]), f)][int(a["phi%"])] = rate(b)
        phis = sorted({p for v in table.values() for p in v})
        print("| N | cells | " + " | ".join(f"phi = {p / 100:.2f}" for p in phis) + " |")
        print("|---|---|" + "---|" * len(phis))
        for (n, f), v in sorted(table.items()):
            cells = "auto" if f == "Scaling" else "1 (one box)"
            print(f"| {n:,} | {cells} | " + " | ".join(f"{v[p]:.2f}" if p in v else "" for p in phis) + " |")
        print("\n(million particle-steps per CPU second)\n")

    if fam["CellsSweep"]:
        print("| cells per axis K | ms per step | particle-steps/s (M) |")
        print("|---|---|---|")
        for a, b in sorted(fam["CellsSweep"], key=lambda x: int(x[0]["K"])):
            steps = max(1, 1000000 // 10000)
            ms = b["cpu_time"] / steps if b["time_unit"] == "ms" else float("nan")
            print(f"| {a['K']} | {ms:.3f} | {rate(b):.2f} |")
        print()

    if fam["Kernel"]:
        by_n = defaultdict(dict)
        for a, b in fam["Kernel"]:
            by_n[int(a["N"])][int(a["specialised"])] = rate(b)
        print("| N (phi = 0.2) | general kernel | specialised | gain |")
        print("|---|---|---|---|")
        for n, v in sorted(by_n.items()):
            if 0 in v and 1 in v:
                print(f"| {n:,} | {v[0]:.2f} | {v[1]:.2f} | {100 * (v[1] / v[0] - 1):+.0f}% |")
        print()

    if fam["Target"]:
        for a, b in fam["Target"]:
            prec = "float" if a.get("float") == "1" else "double"
            print(f"Target N = 100,000, phi = 0.2, dt = 0.01, {prec}: {rate(b):.2f} M particle-steps/s")


if __name__ == "__main__":
    main(sys.argv[1])
