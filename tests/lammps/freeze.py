"""Kinematic spheres in LAMMPS: a `fix freeze` group is a set of kinematic spheres (infinite mass,
no gravity, moving on at the velocity LAMMPS has, as fix freeze leaves velocities alone). A bed
settling on a frozen base ends where the standalone's --kinematic-types run ends; a base given a
velocity ('velocity base set ...': the piston fix move linear would be) moves on its line and
ends where the standalone's does. fix move is refused in errors.yaml (its linear style with this
alternative)."""
import math

from tests.lammps.lammps_runner import Cases, main

cases = Cases(__file__)
BOX = (6.0, 6.0, 12.0)
CLI = ["--boundary", "p,p,w", "--gravity", "0,0,-1", "--dt", 0.005, "--restitution", 0.6, "--kinematic-types", 2]


def bed_file(path, base_velocity):
    """Type 2: a 6 x 6 base of touching unit spheres at z = 0.5; type 1: 30 spheres of diameter 0.9 above."""
    atoms, vels, n = [], [], 0
    for i in range(6):
        for j in range(6):
            n += 1
            atoms.append(f"{n} 2 1.0 1.909859317102744 {0.5 + i} {0.5 + j} 0.5")
            vels.append(f"{n} {base_velocity[0]} {base_velocity[1]} {base_velocity[2]} 0 0 0")
    for k in range(30):
        n += 1
        atoms.append(f"{n} 1 0.9 1.5 {0.6 + (k % 5) * 1.2} {0.6 + (k // 5) % 5 * 1.2} {2.5 + 1.5 * (k // 25)}")
        vels.append(f"{n} {0.3 * math.sin(k)} {0.3 * math.cos(k)} 0 0 0 0")
    path.write_text(f"bed\n\n{n} atoms\n2 atom types\n\n0 {BOX[0]} xlo xhi\n0 {BOX[1]} ylo yhi\n0 {BOX[2]} zlo zhi\n\n"
                    "Atoms # sphere\n\n" + "\n".join(atoms) + "\n\nVelocities\n\n" + "\n".join(vels) + "\n")


def against_standalone(ctx, name, base_velocity):
    bed_file(ctx.work / f"{name}.data", base_velocity)
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
