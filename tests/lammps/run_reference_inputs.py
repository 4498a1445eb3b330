#!/usr/bin/env python3
"""Runs every self-contained reference_inputs/lammps/in.hardsphere_* with lmp (serial and, if
mpirun is given, 2 ranks, fewer steps): each must finish, conserve kinetic energy and collide.
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

from tests.lammps.lammps_runner import ENV, mpi_command, plugin_line, thermo_blocks


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--lmp", required=True)
    ap.add_argument("--plugin", default="", help="hardsphereplugin.so: every input starts with 'plugin load PATH'")
    ap.add_argument("--inputs", required=True)
    ap.add_argument("--mpirun", default="")
    a = ap.parse_args()
    a.lmp = os.path.abspath(a.lmp)
    ok = True
    for path in sorted(glob.glob(os.path.join(a.inputs, "in.hardsphere_*"))):
        if "${data}" in open(path).read():
            continue
        for np_ in ([1, 2] if a.mpirun else [1]):
            with tempfile.TemporaryDirectory() as d:
                # shorter runs: every 'run N' becomes 'run 500'
                text = plugin_line(a.plugin) + re.sub(r"^(run\s+)\d+", r"\g<1>500", open(path).read(), flags=re.M)
                inp = os.path.join(d, "in")
                open(inp, "w").write(text)
                cmd = mpi_command(a.mpirun, np_, [a.lmp, "-in", inp, "-log", "none"])
                p = subprocess.run(cmd, cwd=d, env=ENV, capture_output=True, text=True, timeout=200)
                rows = [r for b in thermo_blocks(p.stdout) for r in b]  # every run's rows
                good = p.returncode == 0 and rows and rows[-1]["f_hs[1]"] > 0 and \
                    abs(rows[-1]["KinEng"] / rows[0]["KinEng"] - 1) < 1e-8
                print(("ok:   " if good else "FAIL: ") + f"{os.path.basename(path)} np={np_}: " +
                      (f"{rows[-1]['f_hs[1]']:.0f} collisions" if rows else (p.stdout + p.stderr)[-2000:]))
                ok &= bool(good)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
