#!/usr/bin/env python3
"""Runs every self-contained reference_inputs/lammps/in.hardsphere_* with lmp (serial and, if
mpirun is given, 2 ranks, fewer steps): each must finish, conserve kinetic energy and collide.
The DEM scenes converted from LAMMPS's examples (in.*_hardsphere, docs/dem_recipe.md) run with
every 'run N' cut to 3000 steps: each must finish with atoms that collided, none overlapping
another in the state it writes (-var out). A scene whose header has a line '# serial only:
REASON' runs on one rank only (the reason is printed).
With --plugin PATH every input starts with `plugin load PATH` (a stock lmp with
hardsphereplugin.so). Inputs that read a data file (-var data) run under compare.cross_validate
(ctest cross_validate_quick); the granular ones are for Debian's lmp (tests/compare).

    python3 -m tests.lammps.run_reference_inputs --lmp PATH --inputs reference_inputs/lammps
                                                [--plugin PATH] [--mpirun PATH]
"""
import argparse
import glob
import os
import re
import subprocess
import sys
import tempfile

from compare.dem_scenes import largest_overlap
from tests.lammps.lammps_runner import ENV, mpi_command, plugin_line, read_data, thermo_blocks


def run_short(a, path, np_, d, steps):
    """The input with every 'run N' cut to `steps`, run in d: the completed process and its rows."""
    text = plugin_line(a.plugin) + re.sub(r"^(run\s+)\d+", rf"\g<1>{steps}", open(path).read(), flags=re.M)
    inp = os.path.join(d, "in")
    open(inp, "w").write(text)
    cmd = mpi_command(a.mpirun, np_, [a.lmp, "-in", inp, "-log", "none", "-var", "out", "end.data"])
    p = subprocess.run(cmd, cwd=d, env=ENV, capture_output=True, text=True, timeout=200)
    # fix pour's warnings ("Less insertions than requested") would split the thermo blocks
    out = "\n".join(ln for ln in p.stdout.splitlines() if not ln.startswith("WARNING"))
    return p, [r for b in thermo_blocks(out) for r in b]


def dem_scene(a, path, np_):
    with tempfile.TemporaryDirectory() as d:
        p, rows = run_short(a, path, np_, d, 3000)
        collisions = rows[-1].get("f_1[1]", 0) if rows else 0
        end = os.path.join(d, "end.data")
        overlap = largest_overlap(read_data(end)) if p.returncode == 0 and os.path.isfile(end) else None
        good = p.returncode == 0 and collisions > 0 and overlap is not None and overlap < 1e-9
        print(("ok:   " if good else "FAIL: ") + f"{os.path.basename(path)} np={np_}: " +
              (f"{rows[-1]['Atoms']:.0f} atoms, {collisions:.0f} collisions, largest overlap {overlap}"
               if p.returncode == 0 and rows else (p.stdout + p.stderr)[-2000:]))
        return good


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--lmp", required=True)
    ap.add_argument("--plugin", default="", help="hardsphereplugin.so: every input starts with 'plugin load PATH'")
    ap.add_argument("--inputs", required=True)
    ap.add_argument("--mpirun", default="")
    a = ap.parse_args()
    a.lmp = os.path.abspath(a.lmp)
    ok = True
    for path in sorted(glob.glob(os.path.join(a.inputs, "in.*_hardsphere"))):
        serial = re.search(r"^# serial only: (.*)$", open(path).read(), flags=re.M)
        for np_ in ([1, 2] if a.mpirun else [1]):
            if np_ > 1 and serial:
                print(f"serial only: {os.path.basename(path)}: {serial.group(1)}")
                continue
            ok &= dem_scene(a, path, np_)
    for path in sorted(glob.glob(os.path.join(a.inputs, "in.hardsphere_*"))):
        if "${data}" in open(path).read():
            continue
        for np_ in ([1, 2] if a.mpirun else [1]):
            with tempfile.TemporaryDirectory() as d:
                p, rows = run_short(a, path, np_, d, 500)  # every run's rows
                good = p.returncode == 0 and rows and rows[-1]["f_hs[1]"] > 0 and \
                    abs(rows[-1]["KinEng"] / rows[0]["KinEng"] - 1) < 1e-8
                print(("ok:   " if good else "FAIL: ") + f"{os.path.basename(path)} np={np_}: " +
                      (f"{rows[-1]['f_hs[1]']:.0f} collisions" if rows else (p.stdout + p.stderr)[-2000:]))
                ok &= bool(good)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
