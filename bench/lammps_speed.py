#!/usr/bin/env python3
"""Atom-steps per second of `lmp_hs` + `fix hardsphere` against the standalone stepper on the
same state (a data file written by `hardsphere run`): serial; serial with `newton off`; serial with
a step-hooked second fix (`fix idle all setforce NULL NULL NULL`, which makes the fix write
LAMMPS's state every step); serial with `path ghosts`; 2 MPI ranks. Best of --repeat runs each
(standalone: CPU time of its step loop; LAMMPS: its loop time). Writes DIR/lammps_speed.md and
DIR/lammps_speed.json with the adapter overhead. Speed is reported, never asserted.

  python3 -m bench.lammps_speed --out DIR [--build DIR] [--hardsphere PATH] [--lmp-hs PATH]
      [--mpirun PATH] [--n 8000 64000] [--repeat 3]
"""
from pathlib import Path

from compare import harness
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
    return harness.hardsphere_json(hs, *opts, cwd=d)


def lammps_output(lmp, d, script, np_, mpirun):
    """Runs `script` with lmp on np_ ranks in d; returns what it printed."""
    (Path(d) / "in.speed").write_text(script)
    cmd = [lmp, "-in", "in.speed", "-log", "none", "-echo", "none"]
    if np_ > 1:
        cmd = [mpirun, "--allow-run-as-root", "--oversubscribe", "-np", str(np_)] + cmd
    return harness.run_program(cmd, cwd=d).stdout


def run_lammps(lmp, d, script, np_, mpirun):
    """Runs `script` with lmp on np_ ranks in d; returns LAMMPS's loop time and the fields of the
    last thermo row."""
    out = lammps_output(lmp, d, script, np_, mpirun)
    return loop_times(out)[-1][0], list(thermo_rows(out)[-1].values())


def lammps(lmp, d, script, np_, mpirun):
    loop, row = run_lammps(lmp, d, script, np_, mpirun)
    return loop, row[3]


def markdown(data, generated):
    lines = ["# lmp_hs against the standalone stepper", "", generated, "",
             f"phi {data['phi']}, dt {data['dt']}, {data['steps']} steps, best of {data['repeat']} runs each; atom-steps "
             "per second (standalone: CPU time of the step loop; LAMMPS: its loop time); overhead = standalone rate / "
             "lmp_hs rate - 1.", "",
             "| N | standalone | lmp_hs serial | overhead | serial, `newton off` | overhead | "
             "serial, another fix (writes every step) | overhead | serial, `path ghosts` | 2 ranks | "
             "collisions (standalone / serial) |", "|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in data["rows"]:
        def rate_and_overhead(label):
            return f"{r[label]:.3g} | {100 * (r['standalone'] / r[label] - 1):+.0f}%"
        lines.append(f"| {r['n']} | {r['standalone']:.3g} | {rate_and_overhead('lmp_hs serial')} | "
                     f"{rate_and_overhead('serial, newton off')} | {rate_and_overhead('lmp_hs serial, another fix')} | "
                     f"{r['lmp_hs serial, path ghosts']:.3g} | {r['lmp_hs 2 ranks']:.3g} | "
                     f"{r['collisions']} / {r['lmp_hs serial collisions']:.0f} |")
    return "\n".join(lines)


def main(argv=None):
    ap = harness.parser(__doc__, programs=("hardsphere", "lmp_hs", "mpirun"))
    ap.add_argument("--n", type=int, nargs="+", default=[8000, 64000])
    ap.add_argument("--phi", type=float, default=0.3)
    ap.add_argument("--dt", type=float, default=0.01)
    ap.add_argument("--steps", type=int, default=500)
    ap.add_argument("--repeat", type=int, default=3, help="best of this many runs per engine")
    a = ap.parse_args(argv)
    session = harness.Session("bench.lammps_speed", a, argv)
    tools = harness.tools(a, need=("hardsphere", "lmp_hs", "mpirun"))
    out = session.out()
    hs, lmp, mpirun = tools["hardsphere"], tools["lmp_hs"], tools["mpirun"]
    rows = []
    with session.workdir() as d:
        for n in a.n:
            standalone(hs, d, "--n", str(n), "--phi", str(a.phi), "--steps", "200", "--dt", str(a.dt),
                       "--write-data", "state.data")
            sa = [standalone(hs, d, "--read-data", "state.data", "--steps", str(a.steps), "--dt", str(a.dt))
                  for _ in range(a.repeat)]
            t_sa = min(j["loop_cpu_seconds"] for j in sa)
            row = {"n": n, "standalone": n * a.steps / t_sa, "collisions": sa[0]["collisions"]}
            for label, np_, extra, newton in VARIANTS:
                script = INPUT.format(data="state.data", newton=newton, skin=0.5, dt=a.dt, extra=extra, thermo=100,
                                      steps=a.steps)
                runs = [lammps(lmp, d, script, np_, mpirun) for _ in range(a.repeat)]
                row[label] = n * a.steps / min(r[0] for r in runs)
                row[label + " collisions"] = runs[0][1]
            rows.append(row)
            session.log(f"N {n}: standalone {row['standalone']:.3g}, lmp_hs serial {row['lmp_hs serial']:.3g} atom-steps/s")
    data = dict(command=session.command, phi=a.phi, dt=a.dt, steps=a.steps, repeat=a.repeat, rows=rows)
    report = session.write_report(out, "lammps_speed", markdown(data, session.generated()), data)
    return session.finish([], report)


if __name__ == "__main__":
    harness.main(main)
