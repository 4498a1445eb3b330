"""Rough spheres: `fix hardsphere tangential_restitution B [friction MU]` is the standalone's
--tangential-restitution B [--friction MU] on LAMMPS's angular velocities (atom_style sphere's
omega, I = 0.4 m r^2 as fix nve/sphere and compute erotate/sphere take it). In serial the same
collisions, positions, velocities and angular velocities as `hardsphere run` on the same data
file (round-off only, as identical.py); on 2 ranks the same where the collisions are elastic in
the normal direction, statistically equal with the TC model (its collision history restarts
when LAMMPS re-neighbours, as restitution.py). compute erotate/sphere, compute temp/sphere and
dump omegax omegay omegaz see the fix's rotation. Groups: identical (the stepper's collisions,
with constant beta and with Walton's friction, between walls, on the owned + ghost path),
energy (e = 1, beta = 1 conserves translational + rotational energy; a fix that stops the
rotation is taken up), ghosts (a thin ghost shell: steps re-run for all atoms carry omega)."""
import numpy as np

from tests.lammps.lammps_runner import Cases, main, read_data, read_dump_frames

cases = Cases(__file__)


def fix_keywords(case):
    """The fix's keywords and the standalone's options of a case's collision law: beta and, if
    given, mu, e and q."""
    fix, cli = f"tangential_restitution {case['beta']}", ["--tangential-restitution", case["beta"]]
    for key, keyword, option in (("mu", "friction", "--friction"), ("e", "restitution", "--restitution"),
                                 ("q", "inertia", "--inertia")):
        if key in case:
            fix += f" {keyword} {case[key]}"
            cli += [option, case[key]]
    return fix, cli


def omega_difference(ctx, ref, other):
    """Largest |dw| between two data files' atoms (both with wx wy wz in Velocities)."""
    a, b = read_data(ctx.path(ref)), read_data(ctx.path(other))
    if a.omega is None or b.omega is None or not np.array_equal(a.ids, b.ids):
        return np.inf
    return float(np.abs(b.omega - a.omega).max())


def against_standalone(ctx, case, data, boundary=("p p p", "p,p,p"), fix_extra=""):
    """The deck rough/gas.lmp and `hardsphere run` from the same data file with the same law:
    the measured values (collisions, wall bounces, energies, state differences) and the
    standalone's JSON summary."""
    fix, cli = fix_keywords(case)
    steps, dt = case["steps"], case["dt"]
    name = case["name"]
    ref = ctx.standalone("--read-data", data, "--boundary", boundary[1], "--steps", steps, "--dt", dt, *cli,
                         "--write-data", f"sa_{name}.data")
    rows = ctx.lammps("rough/gas.lmp", vars=dict(data=data, boundary=boundary[0], dt=dt, steps=steps, every=steps,
                                                 rough=f"{fix} {fix_extra}", out=f"lmp_{name}.data",
                                                 dump=f"w_{name}.dump", masses=ctx.engine_masses(data))).rows
    last = rows[-1]
    periodic = tuple(w == "p" for w in boundary[0].split())
    dx, dv = ctx.difference(f"sa_{name}.data", f"lmp_{name}.data", periodic=periodic)
    frame = read_dump_frames(ctx.path(f"w_{name}.dump"))[-1]
    lmp = read_data(ctx.path(f"lmp_{name}.data"))
    dump_w = np.stack([frame["omegax"], frame["omegay"], frame["omegaz"]], axis=1)
    n = len(lmp)
    return {"collisions": last["f_hs[1]"], "wall bounces": last["f_hs[5]"], "max_dx": dx, "max_dv": dv,
            "max_dw": omega_difference(ctx, f"sa_{name}.data", f"lmp_{name}.data"),
            "dump omega against write_data": float(np.abs(dump_w - lmp.omega).max()),
            "translational energy": last["KinEng"], "rotational energy": last["c_rot"],
            "rotational energy at the start": rows[0]["c_rot"],
            # compute temp/sphere: 3 translational and 3 rotational degrees of freedom per
            # sphere less the 3 of the centre of mass.
            "temp/sphere over the energies": last["c_tsph"] * (6 * n - 3) / 2 / (last["KinEng"] + last["c_rot"]),
            "ghost reruns": last["f_hs[6]"], "P": last["f_hs[10]"]}, \
        dict(standalone=ref, start=rows[0], mean_press=last["f_pav"])


@cases.case
def periodic_gas(ctx, case):
    """A gas from `hardsphere run` with angular velocities at its temperature (the data file's
    Velocities carry wx wy wz; with the case's inertia); both engines read it."""
    case = dict(case, name=case.get("name", "gas"))
    cli = fix_keywords(case)[1]
    data = ctx.state(f"rough_{case['name']}.data", "--n", case["n"], "--phi", case["phi"], *cli)
    return against_standalone(ctx, case, data, fix_extra=case.get("fix", ""))


@cases.case
def between_walls(ctx, case):
    """Walls on z: wall contacts take the tangential rule with the wall as an infinite mass."""
    case = dict(case, name="walls")
    cli = fix_keywords(case)[1]
    ctx.state("rough_walls.data", "--n", 1000, "--phi", 0.3, "--boundary", "p,p,w", *cli)
    return against_standalone(ctx, case, "rough_walls.data", boundary=("p p f", "p,p,w"))


@cases.case
def energy(ctx, case):
    """e = 1, beta = 1 from angular velocities set to zero: translational energy flows into the
    rotation (towards equipartition, half of the total) and the sum stays to round-off at every
    thermo row."""
    ctx.state("energy.data", "--n", 256, "--phi", 0.3)
    rows = ctx.lammps("rough/gas.lmp", vars=dict(data="energy.data", steps=2000, every=100, out="energy_out.data",
                                                 dump="energy.dump", rough="tangential_restitution 1")).rows
    total = np.array([r["KinEng"] + r["c_rot"] for r in rows])
    return {"collisions": rows[-1]["f_hs[1]"], "rotational energy at the start": rows[0]["c_rot"],
            "largest energy drift": float(np.abs(total / total[0] - 1).max()),
            "rotational share at the end": rows[-1]["c_rot"] / total[-1]}, {}


@cases.case
def stopped(ctx, case):
    """A fix python/invoke stops every rotation at the end of step 50: the next step starts from
    those angular velocities (thermo at 50 shows none), so the energy from step 50 on is the
    translational energy left then, and the collisions spin the spheres up again."""
    ctx.state("rough_stop.data", "--n", 500, "--phi", 0.3, "--tangential-restitution", 1)
    rows = ctx.lammps("rough/stopped.lmp", vars=dict(data="rough_stop.data", rough="tangential_restitution 1")).rows
    e = [r["KinEng"] + r["c_rot"] for r in rows]
    return {"rotational energy at the start": rows[0]["c_rot"], "rotational energy after the callback": rows[2]["c_rot"],
            "energy from step 50 to 75": abs(e[3] / e[2] - 1), "rotational energy at step 75": rows[3]["c_rot"]}, {}


@cases.case
def thin_shell(ctx, case):
    """A thin ghost shell (2.3 contact distances), long steps, a dense rough gas (e = 1, beta =
    1): collision chains run past the shell, those steps are re-run for all atoms (on 2 ranks)
    with their angular velocities; total energy stays exact, the collision rate the stepper's."""
    ctx.state("rough_dense.data", "--n", 1000, "--phi", 0.45, "--tangential-restitution", 1)
    ref = ctx.standalone("--read-data", "rough_dense.data", "--steps", 200, "--dt", 0.02,
                         "--tangential-restitution", 1)
    rows = ctx.lammps("rough/ghost_shell.lmp", vars=dict(data="rough_dense.data", dt=0.02, cutoff=2.3,
                                                         rough="tangential_restitution 1")).rows
    e0, e1 = rows[0]["KinEng"] + rows[0]["c_rot"], rows[-1]["KinEng"] + rows[-1]["c_rot"]
    return {"reruns": rows[-1]["f_hs[6]"], "collisions": rows[-1]["f_hs[1]"], "energy drift": abs(e1 / e0 - 1)}, \
        dict(standalone=ref)


if __name__ == "__main__":
    raise SystemExit(main(cases))
