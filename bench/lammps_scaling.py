#!/usr/bin/python3
"""MPI scaling of `lmp_hs` + `fix hardsphere`: the same run serial and on 2 ranks, alternating,
medians of LAMMPS's loop (wall) time; prints a markdown table. Speed is reported, never asserted.

  python3 -m bench.lammps_scaling --hs build/standalone/hardsphere --lmp build/plugin/lmp_hs \
      [--n 64000 1000000] [--phi 0.3 0.45] [--steps 300] [--rounds 3] [--weak 32000] [--timing] [--ceiling]

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
import argparse
import os
import statistics
import subprocess
import tempfile
from pathlib import Path

from bench.lammps_speed import lammps_output, run_lammps
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
    subprocess.run([hs, "run", "--n", str(n), "--phi", str(phi), "--steps", "100", "--quiet", "--write-data", name],
                   cwd=d, check=True, capture_output=True)


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
            raise RuntimeError(f"lmp_hs failed: {err or out}")
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


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--hs", required=True)
    ap.add_argument("--lmp", required=True)
    ap.add_argument("--mpirun", default="mpirun")
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
    a = ap.parse_args()
    hs, lmp = str(Path(a.hs).resolve()), str(Path(a.lmp).resolve())
    print(f"dt {a.dt}, {a.steps} steps, medians of {a.rounds} alternating rounds of LAMMPS's loop time (s)\n")
    ceiling_head = " two uncoupled N/2 runs | ceiling speed-up |" if a.ceiling else ""
    print("| N | phi | serial | 2 ranks | speed-up | cost per sphere-step, 2 ranks / serial | "
          "collisions serial / 2 ranks | re-run steps | forced re-neighbourings |" + ceiling_head)
    print("|---|---|---|---|---|---|---|---|---|" + ("---|---|" if a.ceiling else ""))
    timings = []
    with tempfile.TemporaryDirectory() as d:
        for phi in a.phi:
            for n in a.n:
                data = f"n{n}_phi{phi}.data"
                make_state(hs, d, n, phi, data)
                half = None
                if a.ceiling:
                    half = f"n{n // 2}_phi{phi}.data"
                    make_state(hs, d, n // 2, phi, half)
                res = alternate(lmp, d, data, a.dt, a.steps, a.rounds, a.mpirun, half=half)
                (t1, r1), (t2, r2) = res[1], res[2]
                ceiling = f" {res['pair']:.3g} | {t1 / res['pair']:.2f} |" if a.ceiling else ""
                print(f"| {n} | {phi} | {t1:.3g} | {t2:.3g} | {t1 / t2:.2f} | {2 * t2 / t1:.2f} | "
                      f"{r1[1]:.0f} / {r2[1]:.0f} | {r2[2]:.0f} | {r2[3]:.0f} |" + ceiling, flush=True)
                if a.timing:
                    timings.append((n, phi, part_times(lmp, d, data, a.dt, a.steps, a.mpirun)))
        for n, phi, text in timings:
            print(f"\nN {n}, phi {phi}, 2 ranks:\n```\n{text}```")
        if a.weak:
            print("\nWeak scaling (same density, N per rank fixed):\n")
            ceiling_head = " two uncoupled 1-rank runs | ceiling efficiency |" if a.ceiling else ""
            print("| N per rank | phi | 1 rank | 2 ranks | efficiency |" + ceiling_head)
            print("|---|---|---|---|---|" + ("---|---|" if a.ceiling else ""))
            for phi in a.phi:
                small, big = f"w{a.weak}_phi{phi}.data", f"w{2 * a.weak}_phi{phi}.data"
                make_state(hs, d, a.weak, phi, small)
                make_state(hs, d, 2 * a.weak, phi, big)
                t1s, t2s, pairs = [], [], []
                for _ in range(a.rounds):
                    t1s.append(run(lmp, d, small, 1, a.dt, a.steps, a.mpirun)[0])
                    t2s.append(run(lmp, d, big, 2, a.dt, a.steps, a.mpirun)[0])
                    if a.ceiling:
                        pairs.append(side_by_side(lmp, d, small, a.dt, a.steps))
                t1, t2 = statistics.median(t1s), statistics.median(t2s)
                ceiling = ""
                if a.ceiling:
                    tp = statistics.median(pairs)
                    ceiling = f" {tp:.3g} | {100 * t1 / tp:.0f}% |"
                print(f"| {a.weak} | {phi} | {t1:.3g} | {t2:.3g} | {100 * t1 / t2:.0f}% |" + ceiling, flush=True)


if __name__ == "__main__":
    main()
