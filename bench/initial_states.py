#!/usr/bin/python3
"""Time and structure of initial states made by the hardsphere program (docs/initial_states.md).

For each packing fraction, runs
    HARDSPHERE run --n N --phi PHI --seed K --init INIT --boundary B --steps 0
for seeds K = 1..RUNS and reports how many were made and the median wall time (process start
included). For seed 1 it also writes the state once more (untimed), measures the
compressibility factor Z over --time 0.2 of the event engine from it, and its structure
(compare.packing_structure). Prints one Markdown table row per packing fraction.
Usage, from the repository root:
    python3 -m bench.initial_states HARDSPHERE --n 4000 --phi 0.58 0.60 [--runs 3] [--init dense] [--boundary p]
"""
import argparse
import json
import os
import statistics
import subprocess
import tempfile
import time

from compare import packing_structure as structure


def run(hs, *args):
    start = time.perf_counter()
    p = subprocess.run([hs, "run", *map(str, args)], capture_output=True, text=True)
    return time.perf_counter() - start, p


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("hardsphere")
    ap.add_argument("--n", type=int, required=True)
    ap.add_argument("--phi", type=float, nargs="+", required=True)
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--init", default="auto")
    ap.add_argument("--boundary", default="p")
    a = ap.parse_args()
    periodic = structure.parse_boundary(a.boundary)
    print("| phi | made | median s (min-max) | Z | Q6 | crystal-like | g(sqrt3) | g(2) | note |")
    print("|---|---|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        for phi in a.phi:
            common = ["--n", a.n, "--phi", phi, "--init", a.init, "--boundary", a.boundary, "--steps", 0]
            times, made, note = [], 0, ""
            for seed in range(1, a.runs + 1):
                t, p = run(a.hardsphere, *common, "--seed", seed)
                times.append(t)
                made += p.returncode == 0
                if p.returncode != 0:
                    note = p.stderr.strip().splitlines()[-1].split("error: ")[-1]
            cols = ["", "", "", "", ""]
            data = os.path.join(tmp, "state.data")
            if made and run(a.hardsphere, *common, "--seed", 1, "--write-data", data)[1].returncode == 0:
                _, p = run(a.hardsphere, "--read-data", data, "--boundary", a.boundary, "--engine", "event",
                           "--time", 0.2, "--json", "-")
                z = json.loads(p.stdout)["compressibility_factor"] if p.returncode == 0 else float("nan")
                s = structure.analyse(*structure.read_packing(data), periodic)
                cols = [f"{z:.1f}", f"{s['Q6']:.3f}", f"{s['crystal-like']:.3f}", f"{s['g(sqrt3)']:.2f}",
                        f"{s['g(2)']:.2f}"]
            spread = f"{statistics.median(times):.2f} ({min(times):.2f}-{max(times):.2f})"
            print(f"| {phi} | {made}/{a.runs} | {spread} | " + " | ".join(cols) + f" | {note} |", flush=True)


if __name__ == "__main__":
    main()
