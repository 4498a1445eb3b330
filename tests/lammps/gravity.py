"""`fix gravity` acts on the hard spheres through the stepper's parabolic flights: in serial the
standalone's --gravity collision for collision, on 2 ranks statistically equal; kinetic +
potential energy kept (pe includes fix gravity's energy, measured from z = 0 like the
standalone's); P equals LAMMPS's press averaged over the steps; a varying gravity runs, step by step; a sphere
on a chute (gravity along the periodic x) slides or rolls as the analytic results say."""
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
def varying(ctx, case):
    """fix gravity with a variable magnitude (1 + 0.001 step) runs: its vector, evaluated at the
    end of each step, is the next step's acceleration."""
    bed(ctx)
    rows = ctx.lammps("gravity/bed.lmp", vars=dict(data="bed.data", boundary="p p f", dt=0.005, g="v_m")).rows
    return {"steps run": rows[-1]["Step"]}, {}


def incline(ctx, tilt, hs="restitution 1.0", steps=1000):
    """The last row of decks/gravity/incline.lmp: one sphere on the floor of a chute (x periodic)."""
    out = ctx.lammps("gravity/incline.lmp", vars=dict(tilt=tilt, hs=hs, steps=steps))
    return out.rows[-1], out


@cases.case
def chute(ctx, case):
    """A sphere on an inclined plane made by tilted gravity over a floor (x periodic, g (sin t, 0,
    -cos t), t = 0.5, 1000 steps of 0.01, T = 10). Smooth, frictionless floor: x follows the free
    parabola, v_x = g sin(t) T exactly, and the fix warns that nothing brakes the flow. Rough (beta0
    0, mu 0.1, q 2/5; tan t = 0.546 above mu (1 + q) / q = 0.35): it slides, v_x = g (sin t - mu cos t)
    T within one resting contact's friction impulse mu g cos(t) dt (each step's resting contact takes
    it, gravity adds g sin(t) dt between: |v_x - a T| <= g sin(t) dt = 0.0048). Below that limit
    (t = 0.2) it rolls: a = g sin(t) / (1 + q), within g sin(t) dt = 0.002. Gravity turning every
    step (t = 0.4 sin(0.01 step), a vector of variables): v_x is dt times the sum of the steps'
    g_x, each step flying with the vector fix gravity evaluated at the end of the step before."""
    import math
    smooth, out = incline(ctx, 0.5)
    rough, _ = incline(ctx, 0.5, "tangential_restitution 0.0 friction 0.1")
    rolling, _ = incline(ctx, 0.2, "tangential_restitution 0.0 friction 0.1")
    turning, _ = incline(ctx, "v_turn")
    turned = 0.01 * sum(math.sin(0.4 * math.sin(0.01 * k)) for k in range(1000))
    return {"smooth v_x": smooth["v_vx"], "smooth x": smooth["v_x"],
            "smooth warning": out.text,
            "sliding v_x": rough["v_vx"], "rolling v_x": rolling["v_vx"],
            "turning v_x": turning["v_vx"]}, \
        {"free": 10 * math.sin(0.5), "free_x": (2 + 50 * math.sin(0.5)) % 10,  # wrapped into the box
         "sliding": 10 * (math.sin(0.5) - 0.1 * math.cos(0.5)), "rolling": 10 * math.sin(0.2) / 1.4,
         "turning": turned}


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
