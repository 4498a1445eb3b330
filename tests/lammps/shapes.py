"""fix wall/hardsphere: walls in fix wall/gran's geometry (xplane, yplane, zplane, zcylinder)
with the hard-sphere wall law, the same walls as the standalone's --wall shapes. Serial runs are
the standalone's to rounding (same collisions, final state to 1e-12); on 2 ranks the same
physics (energy kept, nobody through a wall). Bad walls and fix wall/gran are refused naming
what to write instead."""
import numpy as np

from compare.lammps_files import spheres, write_data
from tests.lammps.lammps_runner import Cases, main

cases = Cases(__file__)
RADIUS = 4.0


def drum_state(ctx):
    """Unit spheres on a lattice of spacing 1.1 inside a cylinder of radius RADIUS - 0.6 about the
    z axis, in a box from -5 to 5 across and 6.6 along z, with random velocities."""
    g = np.arange(-3.3, 3.31, 1.1)
    pos = [(x, y, z) for x in g for y in g for z in np.arange(0.55, 6.6, 1.1) if x * x + y * y <= (RADIUS - 0.6) ** 2]
    vel = np.random.default_rng(5).normal(size=(len(pos), 3))
    write_data(ctx.work / "drum.data", spheres(pos, vel, box=[[-5, 5], [-5, 5], [0, 6.6]], mass=1.0,
                                               omega=np.zeros_like(vel)))
    return "drum.data", len(pos)


def drum_commands(fix_line, steps=300):
    return (f"fix hs all hardsphere\n{fix_line}\nthermo_style custom step c_ke c_rmax f_hs[1] f_hs[5]\n"
            f"thermo_modify format float %.17g norm no\nthermo 50\nrun {steps}\nwrite_data drum_end.data\n")


@cases.case
def drop(ctx, case):
    """One sphere dropped 4.503 onto 'wall/hardsphere zplane 2.0 NULL restitution 0.5': it rises
    to e_w^2 of the drop after the bounce, and ends where the standalone's --wall plane puts it."""
    rows = ctx.lammps("shapes/drop.lmp", vars=dict(ew=0.5)).rows
    after = [r for r in rows if r["f_hs[5]"] == 1]
    rebound = after[-1]["v_e"] - 2.5  # vz^2 / 2 + g (z - 2.5): the height above the contact
    ctx.standalone("--read-data", "drop_start.data", "--boundary", "p,p,w", "--gravity", "0,0,-1", "--dt", 0.01,
                   "--steps", 450, "--wall", "plane 0 0 2.0 0 0 1 restitution 0.5", "--write-data", "drop_cli.data")
    dx, dv = ctx.difference("drop_end.data", "drop_cli.data", periodic=(True, True, False))
    return {"wall bounces": rows[-1]["f_hs[5]"], "rebound height over the drop": rebound / 4.503,
            "position against the standalone's": dx, "velocity against the standalone's": dv}, {}


@cases.case
def drum(ctx, case):
    """An elastic gas inside 'wall/hardsphere zcylinder 4': kinetic energy kept, every centre
    within R - 1/2 of the axis, and in serial the standalone's --wall "cylinder z 0 0 4" run."""
    data, n = drum_state(ctx)
    rows = ctx.lammps("shapes/drum.lmp", vars=dict(data=data),
                      commands=drum_commands(f"fix w all wall/hardsphere zcylinder {RADIUS}")).rows
    ref = ctx.standalone("--read-data", data, "--boundary", "w,w,p", "--dt", 0.01, "--steps", 300,
                         "--wall", f"cylinder z 0 0 {RADIUS}", "--write-data", "drum_cli.data")
    dx, dv = ctx.difference("drum_end.data", "drum_cli.data", periodic=(False, False, True))
    return {"atoms": n, "kinetic energy change": abs(rows[-1]["c_ke"] / rows[0]["c_ke"] - 1),
            "largest distance from the axis": max(r["c_rmax"] for r in rows),
            "wall collisions": rows[-1]["f_hs[5]"], "collisions": rows[-1]["f_hs[1]"],
            "position against the standalone's": dx, "velocity against the standalone's": dv}, \
        dict(standalone=ref)


def refused(ctx, commands):
    """The drum's gas followed by `commands`, which must end in a LAMMPS error."""
    data, _ = drum_state(ctx)
    out = ctx.lammps("shapes/drum.lmp", vars=dict(data=data), commands=commands, expect_ok=False)
    return {"exit status": abs(out.returncode), "error": (out.errors or ["(no ERROR line)"])[0]}, {}


@cases.case
def wall_gran(ctx, case):
    return refused(ctx, "fix hs all hardsphere\nfix w all wall/gran hooke 2000 NULL 50 NULL 0.5 0 "
                   "xplane -5 5\nrun 1\n")


@cases.case
def wiggle(ctx, case):
    """One sphere dropped onto 'zplane 2.0 NULL wiggle z 0.3 1.7 restitution 0.5' in two runs
    (200 + 250 steps): the standalone's --wall "plane ... wiggle z 0.3 1.7" run of 450 steps, so
    the wall's time runs on across runs (fix wall/gran's: steps since the fix times dt)."""
    rows = ctx.lammps("shapes/wiggle.lmp", vars=dict(ew=0.5)).rows
    ctx.standalone("--read-data", "wiggle_start.data", "--boundary", "p,p,w", "--gravity", "0,0,-1", "--dt", 0.01,
                   "--steps", 450, "--wall", "plane 0 0 2.0 0 0 1 wiggle z 0.3 1.7 restitution 0.5",
                   "--write-data", "wiggle_cli.data")
    dx, dv = ctx.difference("wiggle_end.data", "wiggle_cli.data", periodic=(True, True, False))
    return {"wall contacts": rows[-1]["f_hs[5]"], "position against the standalone's": dx,
            "velocity against the standalone's": dv}, {}


@cases.case
def wiggle_dim(ctx, case):
    return refused(ctx, "fix hs all hardsphere\nfix w all wall/hardsphere zcylinder 4 wiggle x 1 "
                   "10\nrun 1\n")


@cases.case
def no_fix(ctx, case):
    return refused(ctx, "pair_style zero 1.0\npair_coeff * *\nfix n all nve/sphere\n"
                   "fix w all wall/hardsphere zcylinder 4\nrun 1\n")


@cases.case
def outside(ctx, case):
    """A cylinder narrower than the spheres' lattice: the run's start refuses the atom outside."""
    return refused(ctx, drum_commands("fix w all wall/hardsphere zcylinder 2"))


if __name__ == "__main__":
    raise SystemExit(main(cases))
