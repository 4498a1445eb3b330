#!/usr/bin/python3
"""bench.lammps_scaling on a small gas: the tables it prints (speed-up, weak scaling and the
uncoupled-runs ceiling) are complete, and the serial and 2-rank runs count the same collisions.
Run as `python3 -m tests.lammps.scaling_smoke --lmp PATH --hs PATH [--mpirun PATH]`.
Times are printed, never asserted."""
import argparse
import math
import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def rows(text, first_cell):
    return [[c.strip() for c in ln.strip().strip("|").split("|")] for ln in text.splitlines()
            if ln.startswith(f"| {first_cell} |")]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--lmp", required=True)
    ap.add_argument("--hs", required=True)
    ap.add_argument("--mpirun", default="mpirun")
    a = ap.parse_args()
    out = subprocess.run([sys.executable, "-m", "bench.lammps_scaling", "--hs", a.hs, "--lmp", a.lmp,
                          "--mpirun", a.mpirun, "--n", "2000", "--phi", "0.3", "--steps", "40", "--rounds", "1",
                          "--weak", "1000", "--ceiling"], capture_output=True, text=True, check=True,
                         cwd=ROOT).stdout
    print(out)
    strong, weak = rows(out, "2000"), rows(out, "1000")
    assert len(strong) == 1 and len(strong[0]) == 11, strong
    assert len(weak) == 1 and len(weak[0]) == 7, weak
    serial, ranks2 = strong[0][6].split(" / ")
    assert serial == ranks2 and int(serial) > 0, strong[0][6]
    # times, speed-ups and costs: numbers, finite and non-negative; their values are never checked
    for cell in strong[0][2:6] + strong[0][9:] + weak[0][2:4] + weak[0][5:6]:
        assert math.isfinite(float(cell)) and float(cell) >= 0, strong[0] + weak[0]
    assert re.fullmatch(r"\d+%", weak[0][4]) and re.fullmatch(r"\d+%", weak[0][6]), weak[0]
    print("scaling smoke: tables complete, collisions equal serial and on 2 ranks")


if __name__ == "__main__":
    main()
