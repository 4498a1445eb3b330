#!/usr/bin/env python3
"""Runs every self-contained reference_inputs/lammps/in.hardsphere_* with lmp_hs (serial and, if
mpirun is given, 2 ranks, fewer steps): each must finish, conserve kinetic energy and collide.
Inputs that read a data file (-var data) run under compare/cross_validate.py (ctest
cross_validate_quick); the granular ones are for Debian's lmp (tests/compare)."""
import argparse
import glob
import os
import re
import subprocess
import sys
import tempfile

ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1", OMP_NUM_THREADS="1")

ap = argparse.ArgumentParser()
ap.add_argument("--lmp", required=True)
ap.add_argument("--inputs", required=True)
ap.add_argument("--mpirun", default="")
a = ap.parse_args()
ok = True
for path in sorted(glob.glob(os.path.join(a.inputs, "in.hardsphere_*"))):
    if "${data}" in open(path).read():
        continue
    for np_ in ([1, 2] if a.mpirun else [1]):
        with tempfile.TemporaryDirectory() as d:
            # shorter runs: every 'run N' becomes 'run 500'
            text = re.sub(r"^(run\s+)\d+", r"\g<1>500", open(path).read(), flags=re.M)
            inp = os.path.join(d, "in")
            open(inp, "w").write(text)
            cmd = [a.lmp, "-in", inp, "-log", "none"]
            if np_ > 1:
                cmd = [a.mpirun, "--allow-run-as-root", "--oversubscribe", "-np", str(np_)] + cmd
            p = subprocess.run(cmd, cwd=d, env=ENV, capture_output=True, text=True, timeout=200)
            rows, head = [], None
            for line in p.stdout.splitlines():
                s = line.split()
                if s and s[0] == "Step":
                    head = s
                elif head and len(s) == len(head) and s[0].isdigit():
                    rows.append(dict(zip(head, map(float, s))))
                elif s and s[0] == "Loop":
                    head = None
            good = p.returncode == 0 and rows and rows[-1]["f_hs[1]"] > 0 and \
                abs(rows[-1]["KinEng"] / rows[0]["KinEng"] - 1) < 1e-8
            print(("ok:   " if good else "FAIL: ") + f"{os.path.basename(path)} np={np_}: " +
                  (f"{rows[-1]['f_hs[1]']:.0f} collisions" if rows else (p.stdout + p.stderr)[-2000:]))
            ok &= bool(good)
sys.exit(0 if ok else 1)
