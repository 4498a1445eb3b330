#!/usr/bin/python3
"""Homogeneous cooling state of inelastic hard spheres: the velocity distribution's second Sonine
coefficient a2 = (3/5) <c^4> / <c^2>^2 - 1 (with c the peculiar velocity) against the first
Sonine approximation of van Noije and Ernst (1998),
    a2(e) = 16 (1 - e) (1 - 2 e^2) / (81 - 17 e + 30 e^2 (1 - e))   (three dimensions).

The event engine (exact) runs a dilute gas (phi 0.02, unit spheres, T0 = 1) with restitution e
from a Maxwell-Boltzmann start; a2 is averaged over the dump frames of the second half of the
run (the distribution relaxes to the cooling state within a few collisions per sphere; a much
longer run would let clusters form) and over independent seeds, with the standard error of the
seed means.

  python3 -m compare.hcs --out DIR [--quick] [--build DIR] [--hardsphere PATH] [--work DIR]

Writes DIR/hcs.json, DIR/hcs.md and DIR/hcs_a2.png; exit status 1 if a measured a2 differs from
the theory by more than 4 standard errors plus 0.01 (the first Sonine approximation's own error
at these e). The formula: compare.hard_sphere_theory.a2_van_noije_ernst.
"""
import math
from pathlib import Path

import numpy as np

from compare import hard_sphere_theory as hs_theory
from compare import harness
from compare.lammps_files import read_dump


def a2_of(vel):
    c = vel - vel.mean(axis=0)
    c2 = (c ** 2).sum(axis=1)
    return 0.6 * np.mean(c2 ** 2) / np.mean(c2) ** 2 - 1


def run_seed(hs, e, n, t, seed, d):
    dump = Path(d) / f"hcs_{e}_{seed}.dump"
    harness.run_program([hs, "run", "--n", str(n), "--phi", "0.02", "--restitution", str(e), "--engine", "event",
                         "--time", str(t), "--blocks", "30", "--seed", str(seed), "--dump", str(dump), "--quiet"])
    frames = [np.stack([f["vx"], f["vy"], f["vz"]], axis=1) for f in read_dump(dump)]
    return float(np.mean([a2_of(v) for v in frames[len(frames) // 2:]]))


def measure(hs, es, n, seeds, collisions_per_sphere, d):
    rows = []
    for e in es:
        # Time for about this many collisions per sphere as the gas cools (Haff, Enskog rate at T0 = 1).
        phi = 0.02
        rate = 4 * (6 * phi / math.pi) * hs_theory.contact_value_cs(phi) * math.sqrt(math.pi)
        t = hs_theory.haff_time_for_collisions(collisions_per_sphere, e, rate)
        values = [run_seed(hs, e, n, t, seed, d) for seed in range(1, seeds + 1)]
        err = float(np.std(values, ddof=1) / math.sqrt(len(values))) if len(values) > 1 else float("nan")
        rows.append({"e": e, "a2": float(np.mean(values)), "a2_err": err,
                     "a2_theory": hs_theory.a2_van_noije_ernst(e), "seeds": values, "time": t})
    return rows


def plot(rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    es = np.linspace(0.05, 1.0, 200)
    fig, ax = plt.subplots(figsize=(6, 4))
    ax.plot(es, [hs_theory.a2_van_noije_ernst(e) for e in es], "k-", label="van Noije and Ernst (first Sonine)")
    ax.errorbar([r["e"] for r in rows], [r["a2"] for r in rows], yerr=[r["a2_err"] for r in rows], fmt="o",
                color="tab:red", capsize=3, label="event engine, phi 0.02")
    ax.axhline(0, color="0.7", lw=0.8)
    ax.set_xlabel("normal restitution e")
    ax.set_ylabel("a2 of the homogeneous cooling state")
    ax.set_title("Velocity distribution of the cooling state (N = %d)" % rows[0].get("n", 0))
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main(argv=None):
    ap = harness.parser(__doc__, programs=("hardsphere",), work=True)
    ap.add_argument("--quick", action="store_true", help="e = 0.5 only, 4000 spheres, 4 seeds (~5 s)")
    a = ap.parse_args(argv)
    session = harness.Session("compare.hcs", a, argv)
    hs = harness.tools(a, need=("hardsphere",))["hardsphere"]
    out = session.out()
    es, n, seeds = ([0.5], 4000, 4) if a.quick else ([0.3, 0.5, 0.7, 0.9], 8000, 6)
    with session.workdir() as work:
        rows = measure(hs, es, n, seeds, 10, work)
    for r in rows:
        r["n"] = n
    failures = [f"e {r['e']}: a2 {r['a2']:.4f} +- {r['a2_err']:.4f}, van Noije-Ernst {r['a2_theory']:.4f}"
                for r in rows if abs(r["a2"] - r["a2_theory"]) > 4 * r["a2_err"] + 0.01]
    data = {"rows": rows, "n": n, "seeds": seeds, "seconds": round(session.seconds), "command": session.command}
    lines = ["# Homogeneous cooling state: Sonine coefficient a2", "", session.generated(), "",
             f"Event engine, {n} spheres at phi 0.02, {seeds} seeds per e, frames of the second half of a run of "
             "about 10 collisions per sphere. Pass: within 4 standard errors "
             "+ 0.01 of van Noije and Ernst's first Sonine approximation.", "",
             "| e | a2 measured | a2 van Noije-Ernst |", "|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['e']} | {r['a2']:.4f} ± {r['a2_err']:.4f} | {r['a2_theory']:.4f} |")
    lines += ["", "![a2 against e](hcs_a2.png)", ""]
    plot(rows, out / "hcs_a2.png")
    report = session.write_report(out, "hcs", "\n".join(lines), data)
    for r in rows:
        session.log(f"e {r['e']}: a2 {r['a2']:.4f} +- {r['a2_err']:.4f}, van Noije-Ernst {r['a2_theory']:.4f}")
    return session.finish(failures, report)


if __name__ == "__main__":
    harness.main(main)
