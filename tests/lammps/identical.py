"""fix hardsphere reproduces the standalone stepper on the same state and time step.

The resolver, its ordering and tie-breaks are shared; positions differ only by round-off (LAMMPS
wraps positions at its own rebuilds and shifts ghosts by the box length, the stepper applies
image shifts per pair), which chaotic dynamics amplify to ~1e-9 over 200 steps at phi 0.3. The
bound 1e-6 leaves room; a different collision would show up as an O(0.1) difference.
Groups: gas (the gas, newton off, a big sphere, sweep detection), ghosts (the owned + ghost path
and its ghost shell), walls (a mixture between walls, a dense gas between walls on two axes)."""
from compare import big_sphere_scene
from tests.lammps.lammps_runner import Cases, main

cases = Cases(__file__)


def gas_reference(ctx):
    """The 1000-atom gas at phi 0.3 (init.data) and the standalone's 200 steps of 0.01 (sa.data)."""
    ctx.state("init.data", "--n", 1000, "--phi", 0.3)
    return ctx.standalone("--read-data", "init.data", "--steps", 200, "--dt", 0.01, "--write-data", "sa.data")


def same_run(ctx, ref, out, deck="identical/gas.lmp", pre=""):
    """Collisions and final state of a deck run against the standalone's sa.data."""
    last = ctx.lammps(deck, vars=dict(data="init.data", out=out), pre=pre).last
    dx, dv = ctx.difference("sa.data", out)
    return last, dict(collisions=last["f_hs[1]"], max_dx=dx, max_dv=dv)


@cases.case
def gas(ctx, case):
    ref = gas_reference(ctx)
    last, got = same_run(ctx, ref, "lmp.data")
    # Thermo pressure averaged over every step = n T + W/(3 V t): the standalone's pressure.
    got.update(virial=last["f_hs[3]"], ghost_reruns=last["f_hs[6]"], mean_press=last["f_pav"])
    return got, dict(standalone=ref)


@cases.case
def newton_off(ctx, case):
    """`newton off` (recommended in docs/lammps.md: LAMMPS then skips its reverse communication of
    forces) changes LAMMPS's ghost bookkeeping, not the result."""
    ref = gas_reference(ctx)
    return same_run(ctx, ref, "lmp_n.data", pre="newton off\n")[1], dict(standalone=ref)


@cases.case
def big_sphere(ctx, case):
    """A big heavy sphere (diameter 6, mass 1000) in 2000 unit spheres: the serial fix runs the
    stepper, with its own pass for big spheres, collision for collision."""
    scene = big_sphere_scene.make_scene(2000, 0.2, big=1, big_diameter=6.0, big_mass=1000.0)
    big_sphere_scene.write_scene(ctx.path("big.data"), scene)
    ref = ctx.standalone("--read-data", "big.data", "--steps", 200, "--dt", 0.01, "--write-data", "sa_big.data")
    last = ctx.lammps("identical/plain.lmp", vars=dict(data="big.data", out="lmp_big.data",
                                                       masses=ctx.engine_masses("big.data"))).last
    dx, dv = ctx.difference("sa_big.data", "lmp_big.data")
    return dict(collisions=last["f_hs[1]"], max_dx=dx, max_dv=dv), dict(standalone=ref)


@cases.case
def detect_sweep(ctx, case):
    gas_reference(ctx)
    ref = ctx.standalone("--read-data", "init.data", "--steps", 200, "--dt", 0.01, "--detect", "sweep")
    last = ctx.lammps("identical/detect_sweep.lmp", vars=dict(data="init.data")).last
    return dict(collisions=last["f_hs[1]"]), dict(standalone=ref)


@cases.case
def path_ghosts(ctx, case):
    """The owned + ghost path: on one rank its stepper holds every atom and no ghost."""
    ref = gas_reference(ctx)
    last = ctx.lammps("identical/path_ghosts.lmp", vars=dict(data="init.data")).last
    return dict(collisions=last["f_hs[1]"]), dict(standalone=ref)


@cases.case
def ghost_shell_too_thin(ctx, case):
    """A ghost shell of at most two contact distances cannot hold the partners of the ghosts an
    owned atom meets: refused, naming the remedy."""
    gas_reference(ctx)
    out = ctx.lammps("identical/ghost_shell.lmp", vars=dict(data="init.data", cutoff=1.5), expect_ok=False)
    return dict(refused=out.returncode != 0, output=out.text, remedy=out.text), {}


@cases.case
def thin_ghost_shell(ctx, case):
    """A thin shell (2.3 contact distances) with long steps in a dense gas: collision chains run
    past it within a step, ghost copies disagree with their owners and those steps are re-run for
    all atoms (on 2 ranks); energy stays exact, the collision rate the stepper's."""
    ctx.state("dense.data", "--n", 1000, "--phi", 0.45)
    ref = ctx.standalone("--read-data", "dense.data", "--steps", 200, "--dt", 0.02)
    rows = ctx.lammps("identical/ghost_shell.lmp", vars=dict(data="dense.data", dt=0.02, cutoff=2.3)).rows
    return dict(reruns=rows[-1]["f_hs[6]"], collisions=rows[-1]["f_hs[1]"], kinetic_energy=rows[-1]["KinEng"]), \
        dict(standalone=ref, start=rows[0])


@cases.case
def mixture_walls(ctx, case):
    """Binary mixture (diameters 1 and 0.6, masses by volume) between walls at z = 0, 10: the
    unequal-mass kernel and wall reflection, state written by LAMMPS, read by both, with the
    standalone's masses (engine_masses) bit for bit on every LAMMPS release."""
    ctx.lammps("identical/mixture.lmp", vars=dict(out="poly.data"), np=1)
    ref = ctx.standalone("--read-data", "poly.data", "--boundary", "p,p,w", "--steps", 200, "--dt", 0.005,
                         "--write-data", "sa_poly.data")
    last = ctx.lammps("identical/walls.lmp", vars=dict(data="poly.data", boundary="p p f", dt=0.005,
                                                        out="lmp_poly.data", masses=ctx.engine_masses("poly.data"))).last
    dx, dv = ctx.difference("sa_poly.data", "lmp_poly.data", periodic=(True, True, False))  # z: walls
    return dict(collisions=last["f_hs[1]"], wall_bounces=last["f_hs[5]"], max_dx=dx, max_dv=dv), dict(standalone=ref)


@cases.case
def dense_walls(ctx, case):
    """Dense gas (phi 0.4) between walls on two axes, on the owned + ghost path even at np 1:
    spheres sent into a wall by a collision meet neighbours on the way, and the drift's mirrors are
    undone so the resolver bounces them in time order. Same collisions and bounces as the stepper;
    the second 'run 0' re-checks that no pair overlaps."""
    ctx.state("dense_walls.data", "--n", 3000, "--phi", 0.4, "--boundary", "p,w,w", "--seed", 2)
    ref = ctx.standalone("--read-data", "dense_walls.data", "--boundary", "p,w,w", "--steps", 100, "--dt", 0.01)
    last = ctx.lammps("identical/dense_walls.lmp", vars=dict(data="dense_walls.data", boundary="p f f")).last
    return dict(collisions=last["f_hs[1]"], wall_bounces=last["f_hs[5]"]), dict(standalone=ref)


if __name__ == "__main__":
    raise SystemExit(main(cases))
