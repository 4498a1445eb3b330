#!/usr/bin/env python3
"""lmp_hs loading another LAMMPS's library: with LD_LIBRARY_PATH naming a further LAMMPS build's
lib/ (whose liblammps.so.0 has the same soname as Debian's), lmp_hs must stop with a message
naming both releases and the library found, exit status 1, not crash (its styles share class
layouts with the release they were built against). On 1 and 2 ranks (mpirun given).
(libhardsphere_lammps.so cannot be loaded beside that library at all: the dynamic linker refuses
it for symbols the other release does not have.)

    python3 tests/lammps/library_check.py LMP_HS LIBDIR VERSION [MPIRUN]
"""
import os
import subprocess
import sys
import tempfile
from pathlib import Path

lmp_hs, libdir, version = str(Path(sys.argv[1]).resolve()), sys.argv[2], sys.argv[3]
mpirun = sys.argv[4] if len(sys.argv) > 4 else None
env = dict(os.environ, LD_LIBRARY_PATH=libdir, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
failed = 0
with tempfile.TemporaryDirectory() as work:
    Path(work, "in.test").write_text("units lj\natom_style sphere\n")
    for ranks in ([1, 2] if mpirun else [1]):
        cmd = [lmp_hs, "-in", "in.test", "-log", "none"]
        if ranks > 1:
            cmd = [mpirun, "--allow-run-as-root", "--oversubscribe", "-np", str(ranks)] + cmd
        p = subprocess.run(cmd, cwd=work, env=env, capture_output=True, text=True, timeout=120)
        text = p.stdout + p.stderr
        expected = (f"lmp_hs: error: built against LAMMPS 20210929, but the LAMMPS library loaded is {version} "
                    f"({Path(libdir, 'liblammps.so.0')})")
        checks = {"exit status 1": p.returncode == 1, "the message": expected in text,
                  "once": text.count("lmp_hs: error:") == 1}
        for name, ok in checks.items():
            print(f"{'ok:  ' if ok else 'FAIL:'} lmp_hs with {libdir} on {ranks} rank(s): {name}")
            failed += not ok
        if failed:
            print(f"exit status {p.returncode}:\n{text[-2000:]}")
sys.exit(1 if failed else 0)
