"""`fix hardsphere restitution e` is the standalone's --restitution: in serial the same collisions
and kinetic energy to round-off; on 2 ranks statistically equal (the runs part by rounding, and
the TC model's collision history restarts when LAMMPS re-neighbours). P follows the temperature
inside the steps: it equals LAMMPS's press averaged over the run's steps. A bad value is refused
with its text."""
from tests.lammps.lammps_runner import Cases, main

cases = Cases(__file__)
N_ATOMS = 2000


def reference(ctx):
    ctx.state("init.data", "--n", N_ATOMS, "--phi", 0.1)
    return ctx.standalone("--read-data", "init.data", "--steps", 300, "--dt", 0.02, "--restitution", 0.8)


@cases.case
def cooling(ctx, case):
    ref = reference(ctx)
    rows = ctx.lammps("restitution/inelastic.lmp", vars=dict(data="init.data", dt=0.02, e=0.8)).rows
    ke0, ke1 = rows[0]["KinEng"] * N_ATOMS, rows[-1]["KinEng"] * N_ATOMS  # thermo ke is per atom
    return {"start against the standalone's": abs(ke0 - ref["kinetic_energy_initial"]) / ke0,
            "collisions": rows[-1]["f_hs[1]"], "kinetic energy": ke1, "kinetic energy over the start": ke1 / ke0,
            "P": rows[-1]["f_hs[10]"]}, dict(standalone=ref, mean_press=rows[-1]["f_pav"])


@cases.case
def wall(ctx, case):
    """One sphere dropped 4.503 onto a floor with 'wall_restitution zlo 0.5' (fix gravity 1): its
    flight energy after the bounce is (e_w v0)^2 / 2 above the contact, so it rises to
    e_w^2 4.503 above the contact; the standalone's --wall-restitution zlo=0.5 run from the same
    state ends at the same position and velocity."""
    out = ctx.lammps("restitution/wall_drop.lmp", vars=dict(ew=0.5))
    rows = out.rows
    after = [r for r in rows if r["f_hs[5]"] == 1]
    rebound = after[-1]["v_e"] - 0.5  # vz^2 / 2 + g (z - 0.5): the height it rises to
    ctx.standalone("--read-data", "drop_start.data", "--boundary", "p,p,w", "--gravity", "0,0,-1", "--dt", 0.01,
                   "--steps", 450, "--wall-restitution", "zlo=0.5", "--write-data", "drop_cli.data")
    dx, dv = ctx.difference("drop_end.data", "drop_cli.data", periodic=(True, True, False))
    return {"wall bounces": rows[-1]["f_hs[5]"], "rebound height over the drop": rebound / 4.503,
            "position against the standalone's": dx, "velocity against the standalone's": dv}, {}


@cases.case
def wall_refused(ctx, case):
    """A wall keyword naming a face without a wall (x is periodic) is refused, not ignored."""
    out = ctx.lammps("restitution/wall_drop.lmp", vars=dict(ew="0.5 wall_restitution xlo 0.5"), expect_ok=False)
    return {"exit status": abs(out.returncode), "output": out.text}, {}


@cases.case
def refused(ctx, case):
    reference(ctx)
    out = ctx.lammps("restitution/inelastic.lmp", vars=dict(data="init.data", dt=0.02, e=1.5), expect_ok=False)
    return {"exit status": abs(out.returncode), "output": out.text}, {}


if __name__ == "__main__":
    raise SystemExit(main(cases))
