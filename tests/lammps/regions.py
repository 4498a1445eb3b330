"""fix wall/hardsphere/region: a region's surface as hard-sphere walls. Each region style is read
exactly enough that a serial run equals the standalone's with the same --wall shapes (same
collisions, final state to 1e-9); a plate turning by 'rotate v_theta' carries a sphere as the
library's turning plane does; every region the fix cannot follow exactly, and fix
wall/gran/region, is refused naming what to use."""
import numpy as np

from compare.lammps_files import spheres, write_data
from tests.lammps.lammps_runner import Cases, main

cases = Cases(__file__)
LAW = "restitution 0.8"


def gas(ctx, rmax=3.4):
    """Unit spheres on a lattice of spacing 1.1 within rmax of the z axis, in a box from -5 to 5
    across and from 0 to 6.6 along z, random velocities."""
    g = np.arange(-3.3, 3.31, 1.1)
    pos = [(x, y, z) for x in g for y in g for z in np.arange(0.55, 6.6, 1.1) if x * x + y * y <= rmax ** 2]
    vel = np.random.default_rng(5).normal(size=(len(pos), 3))
    write_data(ctx.work / "gas.data", spheres(pos, vel, box=[[-5, 5], [-5, 5], [0, 6.6]], mass=1.0,
                                              omega=np.zeros_like(vel)))
    return "gas.data"


def against_cli(ctx, region, walls, z_periodic=False, pre="", rmax=3.4, rough=False):
    """The gas inside `region` (a LAMMPS region command's arguments after its ID) against the
    standalone's --wall `walls`, 300 steps; z periodic or walled (round shapes need walls)."""
    data = gas(ctx, rmax)
    tangential = " tangential_restitution 0.5 friction 0.3" if rough else ""
    commands = (f"{pre}region r {region}\nfix hs all hardsphere restitution 0.8{tangential}\n"
                f"fix w all wall/hardsphere/region r {LAW}\n"
                "thermo_style custom step c_ke f_hs[1] f_hs[5]\nthermo_modify format float %.17g norm no\n"
                "thermo 50\nrun 300\nwrite_data end.data\n")
    rows = ctx.lammps("regions/gas.lmp", vars=dict(data=data, bz="p" if z_periodic else "f"),
                      commands=commands).rows
    opts = ["--read-data", data, "--boundary", "w,w,p" if z_periodic else "w,w,w", "--dt", 0.01, "--steps", 300, "--restitution", 0.8,
            "--write-data", "cli.data"] + (["--tangential-restitution", 0.5, "--friction", 0.3] if rough else [])
    for w in walls:
        opts += ["--wall", f"{w} {LAW}"]
    ref = ctx.standalone(*opts)
    dx, dv = ctx.difference("end.data", "cli.data", periodic=(False, False, z_periodic))
    return {"wall collisions": rows[-1]["f_hs[5]"], "collisions": rows[-1]["f_hs[1]"],
            "position against the standalone's": dx, "velocity against the standalone's": dv}, dict(standalone=ref)


@cases.case
def cylinder(ctx, case):
    return against_cli(ctx, "cylinder z 0 0 4 INF INF units box", ["cylinder z 0 0 4"], z_periodic=True)


@cases.case
def lattice_units(ctx, case):
    """A region in lattice units (the region command's default) with lattice spacing 2: read in
    box units, radius 4."""
    return against_cli(ctx, "cylinder z 0 0 2 INF INF", ["cylinder z 0 0 4"], z_periodic=True,
                       pre="lattice sc 0.125\n")


@cases.case
def closed_cylinder(ctx, case):
    """A cylinder with its caps inside the box: tube and two planes."""
    return against_cli(ctx, "cylinder z 0 0 4 0.02 6.58 units box",
                       ["cylinder z 0 0 4 bounds 0.02 6.58", "plane 0 0 0.02 0 0 1", "plane 0 0 6.58 0 0 -1"])


@cases.case
def union_funnel(ctx, case):
    """A cone (open ends) on a cylinder of its lower radius (open top): the funnel's union."""
    pre = ("region cy cylinder z 0 0 3.6 0.02 3 open 2 units box\n"
           "region co cone z 0 0 3.6 4.5 3 6.6 open 1 open 2 units box\n")
    return against_cli(ctx, "union 2 co cy", ["cone z 0 0 3 6.6 3.6 4.5", "cylinder z 0 0 3.6 bounds 0.02 3",
                                              "plane 0 0 0.02 0 0 1"], pre=pre, rmax=3.05)


@cases.case
def turning_cylinder(ctx, case):
    """Rough spheres in a cylinder turned by 'rotate v_t' at 0.5 about its own axis: the
    standalone's cylinder 'rotate 0.5'."""
    return against_cli(ctx, "cylinder z 0 0 4 INF INF units box rotate v_t 0 0 0 0 0 1",
                       ["cylinder z 0 0 4 rotate 0.5"], z_periodic=True, rough=True,
                       pre="variable t equal 0.5*elapsed*dt\n")


@cases.case
def sphere(ctx, case):
    return against_cli(ctx, "sphere 0 0 3.3 4.95 units box", ["sphere 0 0 3.3 4.95"])


@cases.case
def plane_side_out(ctx, case):
    """A plane with 'side out': the spheres on the side its normal points away from."""
    return against_cli(ctx, "plane 3.8 0 0 1 0 0 side out units box", ["plane 3.8 0 0 -1 0 0"], z_periodic=True)


@cases.case
def block(ctx, case):
    return against_cli(ctx, "block -3.8 3.8 -3.9 3.9 INF INF units box",
                       ["plane -3.8 0 0 1 0 0", "plane 3.8 0 0 -1 0 0", "plane 0 -3.9 0 0 1 0",
                        "plane 0 3.9 0 0 -1 0"], z_periodic=True)


@cases.case
def turning_plate(ctx, case):
    """'rotate v_theta' at 2 about the plate's normal: the sliding sphere's v_y grows by mu g dt a
    step (the library's ATurningPlateCarriesASphereRound), it is carried round (angular momentum
    about the axis ~ 3 r mu g t after t = 2) at its height, and the run equals the standalone's
    plane 'rotate 2'."""
    rows = ctx.lammps("regions/turn.lmp").rows
    ctx.standalone("--read-data", "turn_start.data", "--boundary", "w,w,w", "--gravity", "0,0,-1", "--dt", 0.001,
                   "--steps", 2001, "--tangential-restitution", 0,
                   "--wall", "plane 5 5 2 0 0 1 rotate 2 tangential_restitution 0 friction 0.5",
                   "--write-data", "turn_cli.data")
    dx, dv = ctx.difference("turn_end.data", "turn_cli.data", periodic=(False, False, False))
    return {"vy growth per step": rows[4]["v_vy"] - rows[3]["v_vy"], "angular momentum at the end": rows[-1]["v_lz"],
            "height change": abs(rows[-1]["v_z"] - 2.5),
            "position against the standalone's": dx, "velocity against the standalone's": dv}, {}


def refused(ctx, commands):
    data = gas(ctx)
    out = ctx.lammps("regions/gas.lmp", vars=dict(data=data, bz="f"), commands=commands, expect_ok=False)
    return {"exit status": abs(out.returncode), "error": (out.errors or ["(no ERROR line)"])[0]}, {}


def refusal(name, region_lines, fix_line="fix w all wall/hardsphere/region r\n"):
    def fn(ctx, case):
        return refused(ctx, region_lines + "fix hs all hardsphere\n" + fix_line + "run 1\n")
    fn.__name__ = name
    return cases.case(fn)


refusal("wall_gran_region", "region r cylinder z 0 0 4 INF INF units box\n",
        "fix w all wall/gran/region hooke 2000 NULL 50 NULL 0.5 0 region r\n")
refusal("intersect", "region a cylinder z 0 0 4 INF INF units box\nregion b sphere 0 0 3 5 units box\n"
        "region r intersect 2 a b\n")
refusal("move", "variable d equal 0.1*elapsed\nregion r cylinder z 0 0 4 INF INF units box move v_d NULL NULL\n")
# granregion.box's turning container
refusal("block_rotate", "variable t equal 0.1*elapsed\n"
        "region r block -4 4 -4 4 INF INF units box rotate v_t 0 0 0 0 0 1\n")
# granregion.mixer's blades: an intersect of the drum and turning side-out blocks
refusal("mixer", "variable t equal 0.1*elapsed\nregion c cylinder z 0 0 4 0 6.6 side in units box\n"
        "region b1 block -4 4 -0.5 0.5 0 2 side out rotate v_t 0 0 0 0 0 1 units box\n"
        "region b2 block -0.5 0.5 -4 4 0 2 side out rotate v_t 0 0 0 0 0 1 units box\n"
        "region r intersect 3 c b1 b2 side in\n")
refusal("off_axis", "variable t equal 0.1*elapsed\n"
        "region r cylinder z 0 0 4 INF INF units box rotate v_t 1 0 0 0 0 1\n")
refusal("side_out_block", "region r block -1 1 -1 1 1 2 units box side out\n")
refusal("variable_shape", "variable rr equal 4\nregion r sphere 0 0 3 v_rr units box\n")
refusal("inner_face", "region a cylinder z 0 0 4 0.3 3 units box\nregion b cylinder z 0 0 4 3 6.4 units box\n"
        "region r union 2 a b\n")
refusal("prism", "region r prism -4 4 -4 4 0 6 0 0 0 units box\n")


if __name__ == "__main__":
    raise SystemExit(main(cases))
