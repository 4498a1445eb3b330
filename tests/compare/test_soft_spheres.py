"""compare.soft_spheres and the soft-sphere reference inputs (reference_inputs/lammps/
in.granular_hooke, in.granular_hertz, reference_inputs/liggghts/in.granular_hertz).

The engine tests run two head-on collisions (equal spheres, and a diameter-1.4 sphere against a
diameter-1 sphere) in each input and check the force law of soft_spheres against what the engine
does: energy conservation with soft_spheres.elastic_energy, the elastic outcome, the contact
duration against contact_time_*, and the engine's virial pressure against pair_virial / (3V).
Tests needing lmp or liggghts skip when the program is not on PATH.
"""
import math
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest
from scipy import integrate

from compare import soft_spheres as ss
from compare.lammps_files import UNIT_DENSITY, loop_times, read_dump_frames, spheres_from_rows, write_data

ROOT = Path(__file__).resolve().parents[2]
INPUTS = ROOT / "reference_inputs"


# --- closed forms -------------------------------------------------------------------------

@pytest.mark.parametrize("model,k,reff,poisson", [
    ("hooke", 1e4, 0.25, None), ("hooke", 300.0, 0.25, None),
    ("hertz_lammps", 2e5, 0.25, None), ("hertz_lammps", 5e3, 0.35, None),
    ("hertz_liggghts", 3e5, 0.25, 0.3), ("hertz_liggghts", 1e4, 0.2917, 0.45),
])
@pytest.mark.parametrize("kT", [1.0, 0.5])
def test_bh_closed_forms_match_quadrature(model, k, reff, poisson, kT):
    sigma = 1.0  # the contact distance (the integral's upper limit)
    # the pair energies written out from the engines' force laws (not from soft_spheres)
    if model == "hooke":
        a, p = k / 2, 2.0
    elif model == "hertz_lammps":
        a, p = 2 / 5 * k * math.sqrt(reff), 2.5  # integral of kn sqrt(reff d) d
    else:
        a, p = 8 / 15 * k / (2 * (1 - poisson**2)) * math.sqrt(reff), 2.5  # of 4/3 Y* sqrt(reff d) d

    def u(r):
        return a * (sigma - r)**p

    d_bh, _ = integrate.quad(lambda r: 1.0 - math.exp(-u(r) / kT), 0.0, sigma, epsabs=1e-14, epsrel=1e-12,
                             points=[sigma - 0.05, sigma - 0.01], limit=200)
    if model == "hooke":
        shift = ss.bh_shift_hooke(k, kT)
    elif model == "hertz_lammps":
        shift = ss.bh_shift_hertz_lammps(k, reff, kT)
    else:
        shift = ss.bh_shift_hertz_liggghts(k, poisson, reff, kT)
    assert sigma - shift == pytest.approx(d_bh, rel=1e-10, abs=1e-12)
    assert 0 < shift < 0.2


def test_bh_conventions():
    # LIGGGHTS (Y, nu) is LAMMPS Hertz with kn = 4/3 Y / (2 (1 - nu^2)): the same shift
    y, nu, reff = 3e5, 0.3, 0.29
    kn = ss.hertz_kn_from_ymod(y, nu)
    assert kn == pytest.approx(4 / 3 * y / (2 * (1 - nu**2)))
    assert ss.ymod_from_hertz_kn(kn, nu) == pytest.approx(y)
    assert ss.bh_shift_hertz_liggghts(y, nu, reff) == pytest.approx(ss.bh_shift_hertz_lammps(kn, reff))
    # u = A delta^p: Delta scales as (kT / A)^(1/p)
    assert ss.bh_shift_hertz_lammps(2e5, 0.25, kT=2.0) == pytest.approx(
        2**0.4 * ss.bh_shift_hertz_lammps(2e5, 0.25))
    assert ss.bh_shift_hooke(1e4) == pytest.approx(math.sqrt(math.pi / 2e4))


@pytest.mark.parametrize("model,k,poisson", [("hooke", 1e4, None), ("hertz_lammps", 2e5, None),
                                             ("hertz_liggghts", 3e5, 0.3)])
def test_force_is_minus_energy_gradient(model, k, poisson):
    d, h = 0.013, 1e-7
    du = (ss.pair_energy(d + h, model, k, 0.3, poisson) - ss.pair_energy(d - h, model, k, 0.3, poisson)) / (2 * h)
    assert ss.pair_force(d, model, k, 0.3, poisson) == pytest.approx(du, rel=1e-6)
    assert ss.pair_energy(-0.1, model, k, 0.3, poisson) == 0 and ss.pair_force(-0.1, model, k, 0.3, poisson) == 0


def _ode_contact_time(force, meff, v):
    """Head-on contact duration by integrating meff delta'' = -force(delta) from delta = 0."""
    def rhs(t, y):
        return [y[1], -force(max(y[0], 0.0)) / meff]

    def leave(t, y):
        return y[0]
    leave.terminal, leave.direction = True, -1
    sol = integrate.solve_ivp(rhs, (0, 10.0), [0.0, v], events=leave, rtol=1e-11, atol=1e-14, first_step=1e-9,
                              max_step=1e-3)
    return sol.t_events[0][0], sol.y[1, -1]


@pytest.mark.parametrize("v", [0.3, 2.0, 5.0])
def test_contact_times_against_ode(v):
    meff = 0.7329
    t_hooke, v_out = _ode_contact_time(lambda d: 1e4 * d, meff, v)
    assert ss.contact_time_hooke(1e4, meff) == pytest.approx(t_hooke, rel=1e-7)
    assert v_out == pytest.approx(-v, rel=1e-6)
    stiff = ss.hertz_stiffness("hertz_lammps", 2e5, 0.29)
    assert stiff == pytest.approx(2e5 * math.sqrt(0.29))
    t_hertz, _ = _ode_contact_time(lambda d: stiff * d**1.5, meff, v)
    assert ss.contact_time_hertz(stiff, meff, v) == pytest.approx(t_hertz, rel=1e-7)
    assert ss.contact_time_hertz(stiff, meff, v) == pytest.approx(
        3.2181 * (meff / stiff)**0.4 * v**-0.2, rel=1e-4)


def test_energy_and_virial_of_a_periodic_configuration():
    lo, hi = np.array([-1.0, 0.0, 0.0]), np.array([4.0, 5.0, 6.0])
    # a pair across the x boundary (unwrapped coordinates), a bigger sphere touching one of them
    # through the z boundary, and a sphere in nobody's range
    pos = np.array([[-0.8, 2.0, 0.1], [3.75, 2.0, 0.1], [-0.8, 2.0, 5.0 - 6.0 * 3], [1.5, 4.0, 3.0]])
    radius = np.array([0.5, 0.5, 0.65, 0.5])
    i, j, rij, r, delta = ss.contacts(pos, radius, lo, hi)
    got = {(a, b): (d, v) for a, b, d, v in zip(i, j, delta, rij)}
    assert set(got) == {(0, 1), (0, 2)}
    assert got[(0, 1)][0] == pytest.approx(1.0 - 0.45)
    assert got[(0, 1)][1] == pytest.approx([0.45, 0.0, 0.0])
    assert got[(0, 2)][0] == pytest.approx(1.15 - 1.1)
    assert got[(0, 2)][1] == pytest.approx([0.0, 0.0, 1.1])
    reffs = {(0, 1): 0.25, (0, 2): 0.5 * 0.65 / 1.15}
    for model, k, nu in (("hooke", 1e3, None), ("hertz_lammps", 1e4, None), ("hertz_liggghts", 1e4, 0.3)):
        e = sum(ss.pair_energy(got[p][0], model, k, reffs[p], nu) for p in got)
        w = sum(np.linalg.norm(got[p][1]) * ss.pair_force(got[p][0], model, k, reffs[p], nu) for p in got)
        assert ss.elastic_energy(pos, radius, lo, hi, model, k, nu) == pytest.approx(e, rel=1e-12)
        assert ss.pair_virial(pos, radius, lo, hi, model, k, nu) == pytest.approx(w, rel=1e-12)
    assert ss.elastic_energy(pos[:1], radius[:1], lo, hi, "hooke", 1e3) == 0.0
    with pytest.raises(ValueError):
        ss.elastic_energy(pos, radius, lo, hi, "hertz_liggghts", 1e4)


# --- the engines --------------------------------------------------------------------------

KN_HOOKE, KN_HERTZ = 1e4, 2e5
YMOD = ss.ymod_from_hertz_kn(KN_HERTZ, ss.POISSON_LIGGGHTS)
DT, NEQUIL, NRUN, CONTACTSTEPS = 2e-4, 50, 500, 2
BOX = 10.0
# two head-on pairs far apart: (x, y, z, vx, vy, vz, diameter, density); both meet near x = 5 so
# that with 2 MPI ranks the contact straddles the rank boundary
PAIRS = ([(4.45, 2.5, 2.5, 1.0, 0, 0, 1.0, UNIT_DENSITY), (5.55, 2.5, 2.5, -1.0, 0, 0, 1.0, UNIT_DENSITY)],
         [(4.25, 7.5, 7.5, 1.0, 0, 0, 1.4, UNIT_DENSITY), (5.55, 7.5, 7.5, -1.0, 0, 0, 1.0, UNIT_DENSITY)])

ENGINES = {
    "lammps_hooke": ("lmp", INPUTS / "lammps" / "in.granular_hooke", {"kn": KN_HOOKE}, ("hooke", KN_HOOKE, None)),
    "lammps_hertz": ("lmp", INPUTS / "lammps" / "in.granular_hertz", {"kn": KN_HERTZ},
                     ("hertz_lammps", KN_HERTZ, None)),
    "liggghts_hertz": ("liggghts", INPUTS / "liggghts" / "in.granular_hertz", {"ymod": YMOD},
                       ("hertz_liggghts", YMOD, ss.POISSON_LIGGGHTS)),
}


def _write_data(path):
    data = spheres_from_rows([a for pair in PAIRS for a in pair], box=((0.0, BOX),) * 3, title="two collisions")
    # atom_style sphere/granular Velocities rows need the angular velocity too (vx vy vz wx wy wz),
    # which both engines require
    data.omega = np.zeros((len(data), 3))
    write_data(path, data)


def _run(engine, work, ranks=1):
    exe, script, extra, _ = ENGINES[engine]
    if shutil.which(exe) is None:
        pytest.skip(f"{exe} not on PATH")
    work.mkdir(parents=True, exist_ok=True)
    _write_data(work / "two.data")
    variables = dict(data="two.data", dt=DT, nequil=NEQUIL, nrun=NRUN, dumpfile="run.dump", dumpevery=1,
                     contactfile="contact.dump", contactsteps=CONTACTSTEPS, virialfile="virial.txt",
                     blocksteps=1, **extra)
    cmd = [exe, "-in", str(script), "-log", "log.txt", "-screen", "none"]
    for k, v in variables.items():
        cmd += ["-var", k, str(v)]
    if ranks > 1:
        mpirun = shutil.which("mpirun")
        if mpirun is None:
            pytest.skip("mpirun not on PATH")
        cmd = [mpirun, "--allow-run-as-root", "--oversubscribe", "-np", str(ranks)] + cmd
    p = subprocess.run(cmd, cwd=work, capture_output=True, text=True, timeout=120)
    assert p.returncode == 0, (p.stdout + p.stderr)[-3000:]
    return dict(frames=read_dump_frames(work / "run.dump"), contact=read_dump_frames(work / "contact.dump"),
                blocks=ss.read_blocks(work / "virial.txt"), loops=loop_times((work / "log.txt").read_text()))


@pytest.fixture(scope="module")
def engine_run(tmp_path_factory):
    """engine_run(engine, ranks=1): the collision run of an engine, each run once per module."""
    cache = {}

    def get(engine, ranks=1):
        if (engine, ranks) not in cache:
            cache[engine, ranks] = _run(engine, tmp_path_factory.mktemp(f"{engine}_np{ranks}"), ranks)
        return cache[engine, ranks]
    return get


@pytest.fixture(params=list(ENGINES))
def collision(request, engine_run):
    return request.param, engine_run(request.param)


def _positions(frame):
    return np.column_stack([frame["xu"], frame["yu"], frame["zu"]])


def _kinetic(frame):
    mass = UNIT_DENSITY * math.pi / 6 * (2 * frame["radius"])**3
    return 0.5 * float(np.sum(mass * (frame["vx"]**2 + frame["vy"]**2 + frame["vz"]**2)))


def test_output_contract(collision):
    engine, r = collision
    # the equilibration run, then the measured run: last 'Loop time' line
    assert [lp[2] for lp in r["loops"]] == [NEQUIL, NRUN]
    assert [f.timestep for f in r["frames"]] == list(range(NRUN + 1))
    assert [f.timestep for f in r["contact"]] == list(range(CONTACTSTEPS + 1))
    f0, c0 = r["frames"][0], r["contact"][0]
    assert f0["id"].tolist() == [1, 2, 3, 4] and f0["radius"].tolist() == [0.5, 0.5, 0.7, 0.5]
    assert set(c0) >= {"id", "type", "radius", "x", "y", "z"}
    assert np.allclose(_positions(f0), np.column_stack([c0["x"], c0["y"], c0["z"]]), rtol=0, atol=1e-12)
    # the measured run starts after nequil steps of free flight
    assert f0["xu"][0] == pytest.approx(4.45 + NEQUIL * DT, abs=1e-12)
    blocks = r["blocks"]
    assert blocks.shape == (NRUN, 3) and blocks[:, 0].tolist() == list(range(1, NRUN + 1))
    # third column: thermo_temp = sum m v^2 / (3N - 3)
    n = len(f0["id"])
    for f in r["frames"][1::100]:
        assert blocks[f.timestep - 1, 2] == pytest.approx(2 * _kinetic(f) / (3 * n - 3), rel=1e-12)


def test_energy_conservation(collision):
    engine, r = collision
    _, _, _, (model, k, nu) = ENGINES[engine]
    lo, hi = np.zeros(3), np.full(3, BOX)  # the data file's box (LIGGGHTS dumps it with %g)
    kin = np.array([_kinetic(f) for f in r["frames"]])
    pot = np.array([ss.elastic_energy(_positions(f), f["radius"], lo, hi, model, k, nu) for f in r["frames"]])
    e0 = kin[0] + pot[0]
    assert pot[0] == 0 and e0 == pytest.approx(0.5 * (2 + 2.744 + 1), rel=1e-12)
    # the contacts store up to ~3/4 of the energy at once, so a wrong force law or constant in
    # elastic_energy shows as an O(1) error. Velocity Verlet errs by O((omega dt)^2) of the
    # contact energy, omega = pi / t_c: (omega dt)^2 <= 8e-4 here (the stiffest pair, t_c = 0.022
    # at dt = 2e-4). Measured: 1.4e-4 of e0 (Hooke, mostly the step on which a contact starts,
    # where kn delta^2 / 2 with delta <= v dt appears at once), 9e-5 (Hertz).
    assert pot.max() > 0.25 * e0
    assert np.max(np.abs(kin + pot - e0)) < 3e-4 * e0


def test_elastic_outcome_and_contact_time(collision):
    engine, r = collision
    _, _, _, (model, k, nu) = ENGINES[engine]
    frames = r["frames"]
    last = frames[-1]
    for (a, b), pair in zip(((0, 1), (2, 3)), PAIRS):
        m1, m2 = (p[6]**3 for p in pair)
        u1, u2 = pair[0][3], pair[1][3]
        w1 = ((m1 - m2) * u1 + 2 * m2 * u2) / (m1 + m2)
        w2 = ((m2 - m1) * u2 + 2 * m1 * u1) / (m1 + m2)
        # the exit velocities: the integrator errs by O((omega dt)^2) <= 8e-4 of the speed; measured
        # 4e-5 (Hooke), 1e-6 (Hertz)
        assert last["vx"][a] == pytest.approx(w1, abs=2e-4) and last["vx"][b] == pytest.approx(w2, abs=2e-4)
        assert np.all(last["vy"][[a, b]] == 0) and np.all(last["vz"][[a, b]] == 0)
        # contact duration: the frames with an overlap, each one dt apart, against the formula
        gap = np.array([f["xu"][b] - f["xu"][a] - f["radius"][a] - f["radius"][b] for f in frames])
        touching = np.flatnonzero(gap < 0)
        assert len(touching) > 50 and np.all(np.diff(touching) == 1) and gap[-1] > 0
        meff = m1 * m2 / (m1 + m2)
        reff = ss.reduced_radius(pair[0][6] / 2, pair[1][6] / 2)
        if model == "hooke":
            t_c = ss.contact_time_hooke(k, meff)
        else:
            t_c = ss.contact_time_hertz(ss.hertz_stiffness(model, k, reff, nu), meff, abs(u1 - u2))
        assert abs(len(touching) * DT - t_c) <= 1.01 * DT


def test_virial_pressure_is_the_pair_virial(collision):
    engine, r = collision
    _, _, _, (model, k, nu) = ENGINES[engine]
    lo, hi = np.zeros(3), np.full(3, BOX)
    checked = 0
    for f in r["frames"][1:]:
        w = ss.pair_virial(_positions(f), f["radius"], lo, hi, model, k, nu)
        pvir = r["blocks"][f.timestep - 1, 1]
        assert pvir == pytest.approx(w / (3 * BOX**3), rel=1e-9, abs=1e-13)
        checked += w > 0
    assert checked > 100


def test_lammps_hertz_is_liggghts_hertz_with_matching_kn(engine_run):
    """LIGGGHTS's hertz with (Y, nu) and LAMMPS's gran/hertz/history with kn = 4/3 Y / (2 (1 - nu^2))
    follow the same trajectory (both velocity Verlet) up to rounding."""
    a, b = engine_run("lammps_hertz"), engine_run("liggghts_hertz")
    for fa, fb in zip(a["frames"][::25], b["frames"][::25]):
        assert np.allclose(_positions(fa), _positions(fb), rtol=0, atol=1e-11)
        assert np.allclose(fa["vx"], fb["vx"], rtol=0, atol=1e-9)


@pytest.mark.parametrize("engine", ["lammps_hooke", "liggghts_hertz"])
def test_two_ranks_match_serial(engine, engine_run):
    serial, par = engine_run(engine), engine_run(engine, ranks=2)
    assert par["loops"][-1][1] == 2
    for fs, fp in zip(serial["frames"][::50], par["frames"][::50]):
        assert np.allclose(_positions(fs), _positions(fp), rtol=0, atol=1e-11)
        assert np.allclose(fs["vx"], fp["vx"], rtol=0, atol=1e-9)
    assert np.allclose(serial["blocks"], par["blocks"], rtol=1e-9, atol=1e-12)
