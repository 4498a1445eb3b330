"""The fix's outputs: f_ID[9] (Z) and f_ID[10] (P) against the standalone run's
compressibility_factor and pressure on the same state, dt and steps; P == N <T> Z / V and
LAMMPS's own press averaged over the run; the temperature in Z averaged over the steps when it
changes (velocity between runs, a thermostat); the 'timing yes' table's structure; compute
stress/atom summed against press. Serial runs the standalone stepper itself, so Z agrees to
round-off; 2 ranks give the same collisions and the virial to round-off amplified by chaotic
dynamics (identical.py). Groups: pressure, timing, stress_atom, walls, temperature."""
import numpy as np

from tests.lammps.lammps_runner import Cases, main, read_dump_frames

cases = Cases(__file__)


def gas_reference(ctx):
    ctx.state("init.data", "--n", 1000, "--phi", 0.3)
    return ctx.standalone("--read-data", "init.data", "--steps", 200, "--dt", 0.01)


def z_and_p(last):
    """Z, P and N T Z / V of a thermo row (thermo ke is per atom in lj units: T = 2 KE / 3)."""
    z, p = last["f_hs[9]"], last["f_hs[10]"]
    return z, p, last["Atoms"] * (2.0 * last["KinEng"] / 3.0) * z / last["Volume"]


@cases.case
def pressure(ctx, case):
    ref = gas_reference(ctx)
    last = ctx.lammps("outputs/pressure.lmp", vars=dict(data="init.data",
                                                          columns="step atoms vol ke f_hs[1] f_hs[9] f_hs[10]")).last
    z, p, ntzv = z_and_p(last)
    return {"collisions": last["f_hs[1]"], "Z": z, "P": p, "P from Z": p, "P against press": p}, \
        dict(standalone=ref, NTZ_V=ntzv, mean_press=last["f_pav"])


def timing_tables(text, known):
    """The 'timing yes' tables of a run's output: [(header, {part: (min, avg, max)})], and the
    lines that are not rows of the form '  PART  MIN AVG MAX'."""
    lines, tables, bad = text.splitlines(), [], []
    for k, line in enumerate(lines):
        if not line.startswith("fix hardsphere timing over"):
            continue
        rows = {}
        for row in lines[k + 1:k + 1 + len(known)]:
            if not row.startswith("  "):
                break
            *name, lo, avg, hi = row.split()
            try:
                rows[" ".join(name)] = (float(lo), float(avg), float(hi))
            except ValueError:
                bad.append(row)
        tables.append((line, rows))
    return tables, bad


@cases.case
def timing(ctx, case):
    """'timing yes' prints, at the end of each run, the wall time per part of the fix's step over
    the ranks (min / avg / max): one table per run, for that run's steps and rank count, each row a
    known part with three non-negative times in order, the stepper's part and the run's path's
    part present (a part is printed when it took any time); the collisions stay the same. Times
    are never compared with each other or with a clock (the parts of 2 ranks can add up to more
    than LAMMPS's loop time under load)."""
    ref = gas_reference(ctx)
    out = ctx.lammps("outputs/timing.lmp", vars=dict(data="init.data", timing="yes"))
    known = case["parts"]
    tables, bad = timing_tables(out.text, known)
    ranks = f"over {ctx.np} rank{'s' if ctx.mpi else ''}):"
    values = [v for _, rows in tables for t in rows.values() for v in t]
    path_part = case["path part"]["mpi" if ctx.mpi else "serial"]
    return {"tables": len(tables), "loop time lines": len(out.lines("Loop time of")),
            "headers name 100 steps and the ranks": all(h.startswith("fix hardsphere timing over 100 steps")
                                                        and h.endswith(ranks) for h, _ in tables),
            "rows unreadable": len(bad),
            "rows of unknown parts": sum(1 for _, rows in tables for name in rows if name not in known),
            "every row min <= avg <= max": all(lo <= avg <= hi for _, rows in tables for lo, avg, hi in rows.values()),
            "smallest time": min(values) if values else -1.0,
            "stepper part in every table": all("steps (the stepper)" in rows for _, rows in tables),
            "path part in every table": all(path_part in rows for _, rows in tables),
            "collisions": out.last["f_hs[1]"]}, dict(standalone=ref)


@cases.case
def timing_refused(ctx, case):
    gas_reference(ctx)
    out = ctx.lammps("outputs/timing.lmp", vars=dict(data="init.data", timing="maybe"), expect_ok=False)
    return {"exit status": abs(out.returncode), "output": out.text}, {}


@cases.case
def stress_atom(ctx, case):
    """compute stress/atom holds each atom's half of its collisions' virial in the step (as press
    holds the step's total): summed, it is LAMMPS's press at every thermo step (including the first
    of a second run), through atom sorting every 7 steps and, on 2 ranks, atoms changing ranks;
    per atom, 2 ranks give the serial values. Serial runs in either case."""
    gas_reference(ctx)
    got, stress = {}, {}
    for np_ in sorted({1, ctx.np}):
        label = "serial" if np_ == 1 else f"{np_} ranks"
        out = ctx.lammps("outputs/stress_atom.lmp", vars=dict(data="init.data"), np=np_)
        rows = [r for b in out.blocks for r in b]
        last = read_dump_frames(ctx.path("stress.dump"))[-1]  # step 200
        stress[np_] = last.table([f"c_sa[{k}]" for k in range(1, 7)])
        got[f"thermo rows ({label})"] = len(rows)
        got[f"press against summed stress/atom ({label})"] = max(abs(r["Press"] - r["v_pa"]) / abs(r["Press"])
                                                                  for r in rows)
        got[f"mean press ({label})"] = sum(r["Press"] for r in rows) / len(rows)  # the collisions' part is in
    if ctx.mpi:
        same_shape = stress[1].shape == stress[ctx.np].shape
        got["per-atom stress at step 200 against serial"] = float(
            np.abs(stress[ctx.np] - stress[1]).max() / np.abs(stress[1]).max()) if same_shape else np.inf
    return got, {}


@cases.case
def walls(ctx, case):
    """Walls (boundary p p f): V is the box volume, as in the standalone (which reports the wall
    pressures separately)."""
    ctx.lammps("outputs/walls_state.lmp", vars=dict(out="walls.data"), np=1)
    ref = ctx.standalone("--read-data", "walls.data", "--boundary", "p,p,w", "--steps", 200, "--dt", 0.01)
    last = ctx.lammps("outputs/walls.lmp", vars=dict(data="walls.data", boundary="p p f")).last
    z, p, ntzv = z_and_p(last)
    return {"collisions": last["f_hs[1]"], "wall bounces": last["f_hs[5]"], "Z": z, "P": p, "P from Z": p}, \
        dict(standalone=ref, NTZ_V=ntzv)


@cases.case
def temperature(ctx, case):
    """The temperature in Z is averaged over the steps: a velocity change between runs and a
    thermostat acting every step (temp/berendsen) both enter with their duration. Step k of the
    fix uses the temperature at the end of step k - 1, after end_of_step fixes and, at a run's
    first step, after the commands between runs (each run's first row, which repeats the previous
    run's last step, comes later in the log and is kept)."""
    gas_reference(ctx)
    out = ctx.lammps("outputs/temperature.lmp", vars=dict(data="init.data"))
    rows = {int(r["Step"]): r for b in out.blocks for r in b}
    temps = [2.0 * rows[k]["KinEng"] / 3.0 for k in range(200)]
    last = rows[200]
    n, w, tt, z = last["Atoms"], last["f_hs[3]"], last["f_hs[4]"], last["f_hs[9]"]
    t_mean = sum(temps) * 0.01 / tt
    return {"Z": z, "mean T against the first": abs(t_mean / temps[0] - 1)}, \
        dict(Z_from_mean_T=1.0 + w / (3.0 * n * t_mean * tt))


if __name__ == "__main__":
    raise SystemExit(main(cases))
