#!/usr/bin/env python3
"""Atom-steps per second of `lmp_hs` + `fix hardsphere` against the standalone stepper on the
same state (a data file written by `hardsphere run`), serial and on 2 MPI ranks; prints a
markdown table with the adapter overhead. Speed is reported, never asserted.

  python3 -m bench.lammps_speed --hs build/standalone/hardsphere --lmp build/plugin/lmp_hs [--n 8000 64000]
"""
import argparse
import json
import subprocess
import tempfile
from pathlib import Path

from compare.lammps_files import loop_times, thermo_rows

INPUT = """units lj
newton {newton}
atom_style sphere
boundary p p p
read_data {data}
pair_style hardsphere
pair_coeff * *
neighbor {skin} bin
neigh_modify every 1 delay 0 check yes
timestep {dt}
fix hs all hardsphere{extra}
thermo_style custom step temp press f_hs[1]
thermo {thermo}
run {steps}
"""


# A fix hooked into every step that changes nothing (setforce with NULL components): the serial
# fix must then write LAMMPS's x and v every step, the worst case for its adapter.
ANOTHER_FIX = "\nfix idle all setforce NULL NULL NULL"

# (column, MPI ranks, text after 'fix hs all hardsphere', newton setting). `newton off` spares
# LAMMPS the per-step reverse communication of (always zero) forces to periodic ghosts.
VARIANTS = (("lmp_hs serial", 1, "", "on"), ("serial, newton off", 1, "", "off"),
            ("lmp_hs serial, another fix", 1, ANOTHER_FIX, "on"),
            ("lmp_hs serial, path ghosts", 1, " path ghosts", "on"), ("lmp_hs 2 ranks", 2, "", "on"))


def standalone(hs, d, *opts):
    p = subprocess.run([hs, "run", *opts, "--json", "-"], cwd=d, capture_output=True, text=True, check=True)
    return json.loads(p.stdout)


def lammps_output(lmp, d, script, np_, mpirun):
    """Runs `script` with lmp on np_ ranks in d; returns what it printed."""
    (Path(d) / "in.speed").write_text(script)
    cmd = [lmp, "-in", "in.speed", "-log", "none", "-echo", "none"]
    if np_ > 1:
        cmd = [mpirun, "--allow-run-as-root", "--oversubscribe", "-np", str(np_)] + cmd
    return subprocess.run(cmd, cwd=d, capture_output=True, text=True, check=True).stdout


def run_lammps(lmp, d, script, np_, mpirun):
    """Runs `script` with lmp on np_ ranks in d; returns LAMMPS's loop time and the fields of the
    last thermo row."""
    out = lammps_output(lmp, d, script, np_, mpirun)
    return loop_times(out)[-1][0], list(thermo_rows(out)[-1].values())


def lammps(lmp, d, script, np_, mpirun):
    loop, row = run_lammps(lmp, d, script, np_, mpirun)
    return loop, row[3]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--hs", required=True)
    ap.add_argument("--lmp", required=True)
    ap.add_argument("--mpirun", default="mpirun")
    ap.add_argument("--n", type=int, nargs="+", default=[8000, 64000])
    ap.add_argument("--phi", type=float, default=0.3)
    ap.add_argument("--dt", type=float, default=0.01)
    ap.add_argument("--steps", type=int, default=500)
    ap.add_argument("--repeat", type=int, default=3, help="best of this many runs per engine")
    a = ap.parse_args()
    a.hs, a.lmp = str(Path(a.hs).resolve()), str(Path(a.lmp).resolve())
    rows = []
    with tempfile.TemporaryDirectory() as d:
        for n in a.n:
            standalone(a.hs, d, "--n", str(n), "--phi", str(a.phi), "--steps", "200", "--dt", str(a.dt),
                       "--write-data", "state.data")
            sa = [standalone(a.hs, d, "--read-data", "state.data", "--steps", str(a.steps), "--dt", str(a.dt))
                  for _ in range(a.repeat)]
            t_sa = min(j["loop_cpu_seconds"] for j in sa)
            rate_sa = n * a.steps / t_sa
            row = {"n": n, "standalone": rate_sa, "collisions": sa[0]["collisions"]}
            for label, np_, extra, newton in VARIANTS:
                script = INPUT.format(data="state.data", newton=newton, skin=0.5, dt=a.dt, extra=extra, thermo=100,
                                      steps=a.steps)
                runs = [lammps(a.lmp, d, script, np_, a.mpirun) for _ in range(a.repeat)]
                t = min(r[0] for r in runs)
                row[label] = n * a.steps / t
                row[label + " collisions"] = runs[0][1]
            rows.append(row)
    print(f"phi {a.phi}, dt {a.dt}, {a.steps} steps, best of {a.repeat}; atom-steps/s "
          "(standalone: CPU time of the step loop; LAMMPS: its loop time)\n")
    print("| N | standalone | lmp_hs serial | overhead | serial, `newton off` | overhead | "
          "serial, another fix (writes every step) | overhead | "
          "serial, `path ghosts` | 2 ranks | collisions (standalone / serial) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        def rate_and_overhead(label):
            return f"{r[label]:.3g} | {100 * (r['standalone'] / r[label] - 1):+.0f}%"
        print(f"| {r['n']} | {r['standalone']:.3g} | {rate_and_overhead('lmp_hs serial')} | "
              f"{rate_and_overhead('serial, newton off')} | {rate_and_overhead('lmp_hs serial, another fix')} | "
              f"{r['lmp_hs serial, path ghosts']:.3g} | {r['lmp_hs 2 ranks']:.3g} | "
              f"{r['collisions']} / {r['lmp_hs serial collisions']:.0f} |")


if __name__ == "__main__":
    main()
