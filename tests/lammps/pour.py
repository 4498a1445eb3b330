"""Atoms inserted and deleted during a run: fix pour fills an empty box and fix hardsphere takes
up each new set of atoms after the fix's pre_exchange (LAMMPS's rows are written before it, so
its overlap test sees the step's positions). Elastic pour: once the last atoms are in, kinetic
plus potential energy stays constant to rounding; inelastic pour: the bed comes to rest on the
floor. Both: every requested atom inserted, none overlapping another or the floor."""
import numpy as np

from tests.lammps.lammps_runner import Cases, main, read_data, thermo_rows

cases = Cases(__file__)
N_POUR = 300


def bed(ctx, data):
    """Smallest centre distance over diameter (minimum image in x and y) and lowest centre height."""
    d = read_data(ctx.work / data)
    dx = d.pos[:, None, :] - d.pos[None, :, :]
    for k in (0, 1):
        dx[:, :, k] -= d.lengths[k] * np.round(dx[:, :, k] / d.lengths[k])
    r = np.sqrt((dx ** 2).sum(axis=2)) + np.eye(len(d)) * 1e9
    return float(r.min()), float((d.pos[:, 2] - 0.5 * d.diameter).min()), len(d)


def pour(ctx, e, steps):
    out = ctx.lammps("pour/pour.lmp", vars=dict(n=N_POUR, e=e, steps=steps, every=50))
    # fix pour's warnings ("Less insertions than requested") interrupt the thermo block
    rows = thermo_rows("\n".join(ln for ln in out.text.splitlines() if not ln.startswith("WARNING")))
    closest, lowest, n = bed(ctx, "pour_end.data")
    return rows, {"atoms at the end": rows[-1]["Atoms"], "atoms in the data file": n,
                  "closest centres over the diameter": closest, "lowest sphere bottom": lowest,
                  "collisions": rows[-1]["f_hs[1]"]}


@cases.case
def elastic(ctx, case):
    rows, q = pour(ctx, 1.0, 3000)
    full = [r for r in rows if r["Atoms"] == N_POUR]
    energy = np.array([r["c_ke"] + r["c_mz"] for r in full])  # g = 1: potential energy sum m z
    q["energy drift after the last insertion"] = float(np.abs(energy / energy[0] - 1).max())
    q["rows after the last insertion"] = len(full)
    return q, {}


@cases.case
def inelastic(ctx, case):
    rows, q = pour(ctx, 0.5, 4000)
    peak = max(r["c_ke"] for r in rows)
    q["kinetic energy at the end over its peak"] = rows[-1]["c_ke"] / peak
    q["wall collisions"] = rows[-1]["f_hs[5]"]
    return q, {}


@cases.case
def evaporate(ctx, case):
    """An elastic gas loses 5 atoms every 20 steps to fix evaporate: the count falls by exactly
    that, and between deletions the kinetic energy of the atoms left is kept to rounding."""
    ctx.state("gas.data", "--n", 500, "--phi", 0.2)
    commands = ("region everywhere block INF INF INF INF INF INF\nfix hs all hardsphere\n"
                "fix e all evaporate 20 5 everywhere 4767\ncompute ke all ke\n"
                "thermo_style custom step atoms c_ke f_hs[1]\nthermo_modify norm no format float %.17g\n"
                "thermo 1\nrun 200\n")
    rows = ctx.lammps("gas.lmp", vars=dict(data="gas.data"), commands=commands).rows
    kept = [abs(b["c_ke"] / a["c_ke"] - 1) for a, b in zip(rows, rows[1:]) if int(b["Step"]) % 20]
    return {"atoms at the end": rows[-1]["Atoms"], "kinetic energy change between deletions": max(kept),
            "collisions": rows[-1]["f_hs[1]"]}, {}


if __name__ == "__main__":
    raise SystemExit(main(cases))
