#!/usr/bin/python3
"""bench.lammps_scaling on a small gas: the tables of its report (speed-up, weak scaling and the
uncoupled-runs ceiling) are complete, and the serial and 2-rank runs count the same collisions.
Run as `python3 -m tests.lammps.scaling_smoke --lmp PATH --hs PATH [--mpirun PATH]`.
Times are printed, never asserted."""
import argparse
import json
import math
import re
import subprocess
import sys
import tempfile
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
    with tempfile.TemporaryDirectory() as d:
        subprocess.run([sys.executable, "-m", "bench.lammps_scaling", "--hardsphere", a.hs, "--lmp-hs", a.lmp,
                        "--mpirun", a.mpirun, "--n", "2000", "--phi", "0.3", "--steps", "40", "--rounds", "1",
                        "--weak", "1000", "--ceiling", "--out", d], check=True, cwd=ROOT)
        out = (Path(d) / "lammps_scaling.md").read_text()
        tables = json.loads((Path(d) / "lammps_scaling.json").read_text())["tables"]
    print(out)
    strong, weak = rows(out, "2000"), rows(out, "1000")
    assert len(strong) == 1 and len(strong[0]) == 13, strong
    assert len(weak) == 1 and len(weak[0]) == 9, weak
    serial, ranks2 = strong[0][8].split(" / ")
    assert serial == ranks2 and int(serial) > 0, strong[0][8]
    # times, speed-ups and costs: numbers, finite and non-negative; their values are never checked
    for cell in strong[0][4:8] + strong[0][11:] + weak[0][4:6] + weak[0][7:8]:
        assert math.isfinite(float(cell)) and float(cell) >= 0, strong[0] + weak[0]
    assert re.fullmatch(r"\d+%", weak[0][6]) and re.fullmatch(r"\d+%", weak[0][8]), weak[0]
    assert len(tables["strong"]) == 1 and len(tables["weak"]) == 1, tables
    print("scaling smoke: tables complete, collisions equal serial and on 2 ranks")


if __name__ == "__main__":
    main()
