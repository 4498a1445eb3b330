#!/usr/bin/python3
"""MPI scaling of `lmp_hs` + `fix hardsphere`: the same run serial and on 2 ranks, alternating,
medians of LAMMPS's loop (wall) time. Speed is reported, never asserted.

  python3 -m bench.lammps_scaling --out DIR [--build DIR] [--hardsphere PATH] [--lmp-hs PATH]
      [--mpirun PATH] [--n 64000 1000000] [--phi 0.3 0.45] [--steps 300] [--rounds 3] [--weak 32000]
      [--timing] [--ceiling]
  python3 -m bench.lammps_scaling --out DIR --from-json

DIR/lammps_scaling.json keeps the rows of every call (a row per N and phi, a weak-scaling row per
N per rank and phi, a timing table per N and phi; a call replaces the rows it measured, so runs of
different sizes and lengths add up to one report), DIR/lammps_scaling.md shows them all with the
command that measured each; --from-json only renders the markdown again.

Columns: speed-up = serial time / 2-rank time; cost per sphere-step on 2 ranks over serial =
2 x 2-rank time / serial time (all ranks counted); collisions of both runs (equal while the
runs stay deterministic; chaos makes them differ in the last digits over long runs); steps re-run
for all atoms because a ghost copy disagreed with its owner; re-neighbourings forced by the fix.
Weak scaling: 1 rank with N/2 spheres against 2 ranks with N at the same density. --timing adds,
per row, the fix's own table of wall time per part of its step on 2 ranks (`timing yes`).
--ceiling adds, in every round, two uncoupled serial runs of N/2 spheres side by side, one per core
(the slower one's loop time): the work of two ranks with no ghosts, no messages and no waiting, so
serial N / that time is the most any 2-rank run can reach on the machine, and 1 rank / that time
the most weak scaling can.
"""
import os
import statistics
import subprocess
from pathlib import Path

from bench.lammps_speed import lammps_output, run_lammps
from compare import harness
from compare.lammps_files import loop_times

INPUT = """units lj
atom_style sphere
boundary p p p
read_data {data}
pair_style hardsphere
pair_coeff * *
neighbor 0.5 bin
neigh_modify every 1 delay 0 check yes
timestep {dt}
fix hs all hardsphere
thermo_style custom step f_hs[1] f_hs[6] f_hs[7]
thermo {steps}
run {steps}
"""


def make_state(hs, d, n, phi, name):
    harness.run_program([hs, "run", "--n", n, "--phi", phi, "--steps", 100, "--quiet", "--write-data", name], cwd=d)


def run(lmp, d, data, ranks, dt, steps, mpirun):
    """Loop time, collisions, steps re-run for all atoms, forced re-neighbourings."""
    loop, row = run_lammps(lmp, d, INPUT.format(data=data, dt=dt, steps=steps), ranks, mpirun)
    return loop, row[1], row[2], row[3]


def part_times(lmp, d, data, dt, steps, mpirun):
    """The fix's own table of wall time per part ('timing yes') of one 2-rank run."""
    script = INPUT.format(data=data, dt=dt, steps=steps).replace("fix hs all hardsphere", "fix hs all hardsphere timing yes")
    lines = lammps_output(lmp, d, script, 2, mpirun).splitlines()
    start = next(k for k, ln in enumerate(lines) if ln.startswith("fix hardsphere timing"))
    end = next(k for k in range(start + 1, len(lines)) if not lines[k].startswith("  "))
    return "\n".join(lines[start:end]) + "\n"


def side_by_side(lmp, d, data, dt, steps):
    """Loop time of the slower of two serial runs of `data` started together, one per core."""
    script = INPUT.format(data=data, dt=dt, steps=steps)
    procs = []
    for core in (0, 1):
        sub = Path(d) / f"core{core}"
        sub.mkdir(exist_ok=True)
        (sub / "in.speed").write_text(script.replace(f"read_data {data}", f"read_data ../{data}"))
        pin = (lambda c=core: os.sched_setaffinity(0, {c})) if os.cpu_count() >= 2 else None
        procs.append(subprocess.Popen([lmp, "-in", "in.speed", "-log", "none", "-echo", "none"], cwd=sub,
                                      stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, preexec_fn=pin))
    loops = []
    for p in procs:
        out, err = p.communicate()
        if p.returncode != 0:
            raise harness.ProgramError(f"lmp_hs failed: {err or out}")
        loops.append(loop_times(out)[-1][0])
    return max(loops)


def alternate(lmp, d, data, dt, steps, rounds, mpirun, ranks=(1, 2), half=None):
    """Medians over rounds of each rank count's loop time (and its first run's thermo row); with
    `half` (a state of N/2 spheres) also the uncoupled pair of half runs, under key "pair"."""
    runs = {r: [] for r in ranks}
    pairs = []
    for _ in range(rounds):
        for r in ranks:
            runs[r].append(run(lmp, d, data, r, dt, steps, mpirun))
        if half:
            pairs.append(side_by_side(lmp, d, half, dt, steps))
    out = {r: (statistics.median(x[0] for x in v), v[0]) for r, v in runs.items()}
    if half:
        out["pair"] = statistics.median(pairs)
    return out


def markdown(store):
    strong, weak, timing = store.rows("strong"), store.rows("weak"), store.rows("timing")
    lines = ["# MPI scaling of lmp_hs + fix hardsphere", "",
             "Medians over alternating rounds of LAMMPS's loop (wall) time, serial and on 2 ranks (s). Speed-up = "
             "serial / 2 ranks; cost per sphere-step on 2 ranks over serial = 2 x 2-rank time / serial time (all ranks "
             "counted); collisions of both runs (equal while the runs stay deterministic); steps re-run for all atoms "
             "because a ghost copy disagreed with its owner; re-neighbourings forced by the fix. The ceiling: two "
             "uncoupled serial runs of N/2 spheres side by side, one per core, measured in the same rounds (the "
             "slower one's loop time): the work of two ranks with no ghosts, no messages and no waiting, so serial / "
             "their time bounds the speed-up of any 2-rank run on the machine, and 1 rank / their time its weak "
             "scaling.", "", "Measured by " + "; ".join(harness.measured_by(strong + weak + timing)) + ".", ""]
    if strong:
        lines += ["| N | phi | steps | rounds | serial (s) | 2 ranks (s) | speed-up | cost per sphere-step, 2 ranks / serial "
                  "| collisions serial / 2 ranks | re-run steps | forced re-neighbourings | two uncoupled N/2 runs (s) "
                  "| ceiling speed-up |", "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
        for r in sorted(strong, key=lambda r: (r["n"], r["phi"])):
            t1, t2, pair = r["serial"], r["ranks2"], r.get("pair")
            ceiling = f"{pair:.3g} | {t1 / pair:.2f}" if pair else "- | -"
            lines.append(f"| {r['n']} | {r['phi']} | {r['steps']} | {r['rounds']} | {t1:.3g} | {t2:.3g} | {t1 / t2:.2f} | "
                         f"{2 * t2 / t1:.2f} | {r['collisions_serial']:.0f} / {r['collisions_ranks2']:.0f} | "
                         f"{r['reruns']:.0f} | {r['reneighbourings']:.0f} | {ceiling} |")
        lines.append("")
    if weak:
        lines += ["Weak scaling (same density, N per rank fixed):", "",
                  "| N per rank | phi | steps | rounds | 1 rank (s) | 2 ranks (s) | weak-scaling efficiency | "
                  "two uncoupled 1-rank runs (s) | ceiling efficiency |", "|---|---|---|---|---|---|---|---|---|"]
        for r in sorted(weak, key=lambda r: (r["n_per_rank"], r["phi"])):
            pair = r.get("pair")
            ceiling = f"{pair:.3g} | {100 * r['rank1'] / pair:.0f}%" if pair else "- | -"
            lines.append(f"| {r['n_per_rank']} | {r['phi']} | {r['steps']} | {r['rounds']} | {r['rank1']:.3g} | "
                         f"{r['ranks2']:.3g} | {100 * r['rank1'] / r['ranks2']:.0f}% | {ceiling} |")
        lines.append("")
    for r in sorted(timing, key=lambda r: (r["n"], r["phi"])):
        lines += [f"`timing yes` on 2 ranks, N {r['n']}, phi {r['phi']}, {r['steps']} steps:", "", "```",
                  r["table"].rstrip("\n"), "```", ""]
    return "\n".join(lines)


def main(argv=None):
    ap = harness.parser(__doc__, programs=("hardsphere", "lmp_hs", "mpirun"))
    ap.add_argument("--n", type=int, nargs="+", default=[64000, 1000000])
    ap.add_argument("--phi", type=float, nargs="+", default=[0.3, 0.45])
    ap.add_argument("--dt", type=float, default=0.01)
    ap.add_argument("--steps", type=int, default=300)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--weak", type=int, default=32000, help="spheres per rank of the weak-scaling rows (0: none)")
    ap.add_argument("--timing", action="store_true",
                    help="after each row, one more 2-rank run with 'timing yes': the fix's time per part")
    ap.add_argument("--ceiling", action="store_true",
                    help="also two uncoupled serial runs of N/2 side by side: what 2 ranks could reach at most")
    ap.add_argument("--from-json", action="store_true", help="render DIR/lammps_scaling.md from its JSON only")
    a = ap.parse_args(argv)
    session = harness.Session("bench.lammps_scaling", a, argv)
    store = harness.RowStore(session.out(), "lammps_scaling")
    if a.from_json:
        return session.finish([], store.render(markdown(store)))
    tools = harness.tools(a, need=("hardsphere", "lmp_hs", "mpirun"))
    hs, lmp, mpirun = tools["hardsphere"], tools["lmp_hs"], tools["mpirun"]
    common = dict(steps=a.steps, rounds=a.rounds, dt=a.dt)
    with session.workdir() as d:
        for phi in a.phi:
            for n in a.n:
                data = f"n{n}_phi{phi}.data"
                make_state(hs, d, n, phi, data)
                half = None
                if a.ceiling:
                    half = f"n{n // 2}_phi{phi}.data"
                    make_state(hs, d, n // 2, phi, half)
                res = alternate(lmp, d, data, a.dt, a.steps, a.rounds, mpirun, half=half)
                (t1, r1), (t2, r2) = res[1], res[2]
                store.put("strong", (n, phi), dict(common, n=n, phi=phi, serial=t1, ranks2=t2, pair=res.get("pair"),
                                                   collisions_serial=r1[1], collisions_ranks2=r2[1], reruns=r2[2],
                                                   reneighbourings=r2[3]), session)
                session.log(f"N {n} phi {phi}: serial {t1:.3g} s, 2 ranks {t2:.3g} s")
                if a.timing:
                    store.put("timing", (n, phi), dict(common, n=n, phi=phi,
                                                       table=part_times(lmp, d, data, a.dt, a.steps, mpirun)), session)
        if a.weak:
            for phi in a.phi:
                small, big = f"w{a.weak}_phi{phi}.data", f"w{2 * a.weak}_phi{phi}.data"
                make_state(hs, d, a.weak, phi, small)
                make_state(hs, d, 2 * a.weak, phi, big)
                t1s, t2s, pairs = [], [], []
                for _ in range(a.rounds):
                    t1s.append(run(lmp, d, small, 1, a.dt, a.steps, mpirun)[0])
                    t2s.append(run(lmp, d, big, 2, a.dt, a.steps, mpirun)[0])
                    if a.ceiling:
                        pairs.append(side_by_side(lmp, d, small, a.dt, a.steps))
                t1, t2 = statistics.median(t1s), statistics.median(t2s)
                store.put("weak", (a.weak, phi), dict(common, n_per_rank=a.weak, phi=phi, rank1=t1, ranks2=t2,
                                                      pair=statistics.median(pairs) if pairs else None), session)
                session.log(f"weak {a.weak} per rank, phi {phi}: 1 rank {t1:.3g} s, 2 ranks {t2:.3g} s")
    return session.finish([], store.render(markdown(store)))


if __name__ == "__main__":
    harness.main(main)
