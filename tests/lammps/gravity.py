"""`fix gravity` acts on the hard spheres through the stepper's parabolic flights: in serial the
standalone's --gravity collision for collision, on 2 ranks statistically equal; kinetic +
potential energy kept (pe includes fix gravity's energy, measured from z = 0 like the
standalone's); P equals LAMMPS's press averaged over the steps; a varying gravity is refused."""
from tests.lammps.lammps_runner import Cases, main

cases = Cases(__file__)
N_ATOMS = 500


def bed(ctx):
    """500 spheres in a 10 x 10 x 40 box with walls on z (bed.data), and the standalone's 1000
    steps of 0.005 under gravity 1 along -z."""
    ctx.state("bed.data", "--n", N_ATOMS, "--box", "10,10,40", "--boundary", "p,p,w")
    return ctx.standalone("--read-data", "bed.data", "--boundary", "p,p,w", "--gravity", "0,0,-1", "--steps", 1000,
                          "--dt", 0.005)


@cases.case
def falling(ctx, case):
    ref = bed(ctx)
    rows = ctx.lammps("gravity/bed.lmp", vars=dict(data="bed.data", boundary="p p f", dt=0.005, g=1.0)).rows
    first, last = rows[0], rows[-1]
    ke0, ke1 = first["KinEng"] * N_ATOMS, last["KinEng"] * N_ATOMS
    return {"P": last["f_hs[10]"], "collisions": last["f_hs[1]"], "wall bounces": last["f_hs[5]"],
            "kinetic energy": ke1, "kinetic energy over the start": ke1 / ke0,
            "kinetic + potential energy": (last["KinEng"] + last["PotEng"]) * N_ATOMS}, \
        dict(standalone=ref, mean_press=last["f_pav"], start=(first["KinEng"] + first["PotEng"]) * N_ATOMS)


@cases.case
def spherical(ctx, case):
    """LAMMPS's own idiom for -z, 'spherical 0.0 -180.0', whose x component is -1.2e-16 from
    rounding: the same run as 'vector 0 0 -1', not a gravity along the periodic x."""
    ref = bed(ctx)
    rows = ctx.lammps("gravity/bed.lmp", vars=dict(data="bed.data", boundary="p p f", dt=0.005, g=1.0,
                                                    direction="spherical 0.0 -180.0")).rows
    return {"collisions": rows[-1]["f_hs[1]"]}, dict(standalone=ref)


@cases.case
def settled_lattice(ctx, case):
    """The fix starts from every state it ends with: 100 spheres on lattice sites settle in exact
    columns (restitution 0.27) whose contacts the rounding leaves a few 1e-16 inside contact; the
    next 'run 0' and 'run 10' start from that state on both paths. The state written after the
    first run is read by the standalone, within its overlap tolerance."""
    got, refs = {}, {}
    for path in ("auto", "ghosts"):
        out = ctx.lammps("gravity/lattice_bed.lmp", vars=dict(path=path, out=f"bed_{path}.data"), expect_ok=False)
        got[f"{path} path, runs completed"] = len(out.lines("Loop time"))
        got[f"{path} path, exit status"] = out.returncode
        if out.returncode:
            print("\n".join(out.errors[:2]))
        read = ctx.standalone("--read-data", f"bed_{path}.data", "--boundary", "p,p,w", "--steps", 0)
        got[f"{path} path, largest overlap at the end"] = read["max_overlap"]
        refs[path] = read
    return got, refs


@cases.case
def varying_refused(ctx, case):
    bed(ctx)
    out = ctx.lammps("gravity/bed.lmp", vars=dict(data="bed.data", boundary="p p f", dt=0.005, g="v_m"),
                     expect_ok=False)
    return {"exit status": abs(out.returncode), "output": out.text}, {}


@cases.case
def resting(ctx, case):
    """Spheres created at rest on the floor stay at rest on both paths (the serial or 2-rank one and
    the owned + ghost one): heights above their contacts, the kinetic energy after 2000 steps."""
    out = {}
    for path in ("auto", "ghosts"):
        last = ctx.lammps("gravity/rest.lmp", vars=dict(path=path)).rows[-1]
        out[f"{path} path, highest height above the contact"] = max(last[k] for k in ("v_z1", "v_z2", "v_z3"))
        out[f"{path} path, lowest height above the contact"] = min(last[k] for k in ("v_z1", "v_z2", "v_z3"))
        out[f"{path} path, kinetic energy"] = last["KinEng"] * 3
        out[f"{path} path, wall bounces"] = last["f_hs[5]"]
    return out, {}


if __name__ == "__main__":
    raise SystemExit(main(cases))
