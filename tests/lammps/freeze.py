"""Kinematic spheres in LAMMPS: a `fix freeze` group is a set of kinematic spheres (infinite mass,
no gravity, moving on at the velocity LAMMPS has, as fix freeze leaves velocities alone). A bed
settling on a frozen base ends where the standalone's --kinematic-types run ends; a base given a
velocity ('velocity base set ...': the piston fix move linear would be) moves on its line and
ends where the standalone's does. fix move is refused in errors.yaml (its linear style with this
alternative)."""

from tests.frozen_bed import write_bed
from tests.lammps.lammps_runner import Cases, main

cases = Cases(__file__)
CLI = ["--boundary", "p,p,w", "--gravity", "0,0,-1", "--dt", 0.005, "--restitution", 0.6, "--kinematic-types", 2]


def against_standalone(ctx, name, base_velocity):
    write_bed(ctx.work / f"{name}.data", base_velocity)
    ctx.lammps("freeze/bed.lmp", vars=dict(data=f"{name}.data", steps=1000, out=f"{name}_end.data",
                                           masses=ctx.engine_masses(f"{name}.data")))
    ref = ctx.standalone("--read-data", f"{name}.data", *CLI, "--steps", 1000, "--write-data", f"{name}_cli.data")
    dx, dv = ctx.difference(f"{name}_end.data", f"{name}_cli.data", periodic=(True, True, False))
    return {"position against the standalone's": dx, "velocity against the standalone's": dv,
            "kinematic collisions": ref["kinematic_collisions"]}, dict(standalone=ref)


@cases.case
def base(ctx, case):
    return against_standalone(ctx, "base", (0.0, 0.0, 0.0))


@cases.case
def piston(ctx, case):
    return against_standalone(ctx, "piston", (0.2, 0.0, 0.0))


if __name__ == "__main__":
    raise SystemExit(main(cases))
