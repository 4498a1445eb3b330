"""Unit styles other than lj: the dynamics use x, v, dt and masses as they are, so the same numbers
give the same collisions; Z is a ratio and stays; P (f_ID[10]) and the virial the fix hands LAMMPS
come in the style's pressure and energy units, so f_ID[10] equals LAMMPS's own press averaged over
the run; fix gravity's force per mass becomes the acceleration LAMMPS's integrators would give
(kinetic + potential energy kept). No length or time scale is built in: the gas scaled to
millimetre spheres (SI granular work), to nanometres and up by 10^6, with the time step scaled
alike, collides as the unscaled one. Groups: styles, scales."""
from tests.lammps.lammps_runner import Cases, main, read_data

cases = Cases(__file__)


def gas_reference(ctx):
    ctx.state("init.data", "--n", 1000, "--phi", 0.3)
    return ctx.standalone("--read-data", "init.data", "--steps", 200, "--dt", 0.01)


def bed_reference(ctx):
    ctx.state("bed.data", "--n", 500, "--box", "10,10,40", "--boundary", "p,p,w")
    return ctx.standalone("--read-data", "bed.data", "--boundary", "p,p,w", "--gravity", "0,0,-1", "--steps", 1000,
                          "--dt", 0.005)


@cases.case
def pressure(ctx, case):
    """P in the style's units: the standalone's (lj) P x mvv2e x nktv2p."""
    ref = gas_reference(ctx)
    last = ctx.lammps("outputs/pressure.lmp", vars=dict(data="init.data", units=case["style"],
                                                          columns="step f_hs[1] f_hs[9] f_hs[10]")).last
    p = last["f_hs[10]"]
    return {"collisions": last["f_hs[1]"], "Z": last["f_hs[9]"], "P": p, "P against press": p}, \
        dict(standalone=ref, P_in_units=ref["pressure"] * case["mvv2e"] * case["nktv2p"], mean_press=last["f_pav"])


@cases.case
def gravity(ctx, case):
    """A force per mass of mvv2e is an acceleration of 1: the standalone's --gravity 0,0,-1."""
    ref = bed_reference(ctx)
    rows = ctx.lammps("units/gravity.lmp", vars=dict(data="bed.data", units=case["style"], boundary="p p f",
                                                      dt=0.005, g=repr(case["mvv2e"]))).rows
    first, last = rows[0], rows[-1]
    return {"collisions": last["f_hs[1]"], "kinetic + potential energy": last["KinEng"] + last["PotEng"],
            "kinetic energy over the start": last["KinEng"] / first["KinEng"]}, \
        dict(standalone=ref, start=first["KinEng"] + first["PotEng"])


@cases.case
def scaled(ctx, case):
    """Scaled positions round differently: Z to 1e-9, the collisions exactly."""
    ref = gas_reference(ctx)
    scale = case["scale"]
    length = read_data(ctx.path("init.data")).lengths[0]
    last = ctx.lammps("units/scaled.lmp", vars=dict(data="init.data", skin=0.5 * scale, dt=0.01 * scale,
                                                     length=repr(float(length * scale)), scale=repr(scale))).last
    return {"collisions": last["f_hs[1]"], "Z": last["f_hs[9]"]}, dict(standalone=ref)


if __name__ == "__main__":
    raise SystemExit(main(cases))
