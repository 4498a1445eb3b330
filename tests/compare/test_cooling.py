"""compare.cooling's closed forms (in compare.soft_spheres and compare.hard_sphere_theory): the
gran/hooke damping for a restitution against a numerical integration of the damped contact, Haff's
law and its limits, and the small helpers of its runs and report. The engine runs themselves are
the ctest cooling_quick (python3 -m compare.cooling --quick)."""
import math

import numpy as np
import pytest
from scipy import integrate

from compare import cooling_report, cooling_runs
from compare import hard_sphere_theory as hs_theory
from compare import soft_spheres as soft
from compare.lammps_files import read_data


def _damped_contact(kn, gamman, meff, v):
    """Integrates meff delta'' = -kn delta - meff gamman delta' (LAMMPS gran/hooke's normal force)
    from delta = 0 at approach speed v until delta returns to 0: (exit speed / v, duration)."""
    def rhs(t, y):
        return [y[1], -kn / meff * y[0] - gamman * y[1]]

    def leave(t, y):
        return y[0]
    leave.terminal, leave.direction = True, -1
    sol = integrate.solve_ivp(rhs, (0, 10.0), [0.0, v], events=leave, rtol=1e-11, atol=1e-14, first_step=1e-9,
                              max_step=1e-3)
    return -sol.y[1, -1] / v, sol.t_events[0][0]


@pytest.mark.parametrize("e", [0.99, 0.9, 0.7, 0.3])
@pytest.mark.parametrize("kn,meff", [(1.5708e4, 0.5), (2.5e5, 0.5), (300.0, 0.7329)])
def test_gamman_gives_the_restitution_of_the_damped_contact(e, kn, meff):
    gamman = soft.gamman_for_restitution(e, kn, meff)
    assert gamman > 0
    for v in (0.2, 1.0, 5.0):  # linear: the same e at every speed
        ratio, duration = _damped_contact(kn, gamman, meff, v)
        assert ratio == pytest.approx(e, rel=1e-7)
        assert duration == pytest.approx(soft.hooke_contact_time(gamman, kn, meff), rel=1e-7)
    assert soft.hooke_restitution(gamman, kn, meff) == pytest.approx(e, rel=1e-12)


def test_gamman_conventions():
    kn, meff = 1e4, 0.5
    assert soft.gamman_for_restitution(1.0, kn, meff) == 0.0
    # e = exp(-pi beta / sqrt(1 - beta^2)) with beta = meff gamman / (2 sqrt(kn meff))
    e = 0.8
    beta = meff * soft.gamman_for_restitution(e, kn, meff) / (2 * math.sqrt(kn * meff))
    assert math.exp(-math.pi * beta / math.sqrt(1 - beta**2)) == pytest.approx(e, rel=1e-12)
    # the elastic contact time pi sqrt(meff / kn) without damping
    assert soft.hooke_contact_time(0.0, kn, meff) == pytest.approx(math.pi * math.sqrt(meff / kn))
    for bad in (0.0, -0.5, 1.2):
        with pytest.raises(ValueError):
            soft.gamman_for_restitution(bad, kn, meff)


def test_enskog_rate_of_unit_spheres():
    phi, t0 = 0.05, 1.7
    n = 6 * phi / math.pi
    g = (1 - phi / 2) / (1 - phi) ** 3
    assert cooling_runs.enskog_rate(phi, t0) == pytest.approx(4 * n * g * math.sqrt(math.pi * t0), rel=1e-12)


def test_haff_limits():
    t0, gamma0 = 1.3, 0.77
    t = np.linspace(0, 50, 11)
    # elastic: no cooling
    assert np.allclose(hs_theory.haff_temperature(t, t0, 1.0, gamma0), t0, rtol=0, atol=0)
    for e in (0.9, 0.7):
        assert hs_theory.haff_temperature(0.0, t0, e, gamma0) == t0
        # small t: dT/dt = -(1 - e^2) Gamma0 T0 / 3
        h = 1e-6
        slope = (hs_theory.haff_temperature(h, t0, e, gamma0) - hs_theory.haff_temperature(-h, t0, e, gamma0)) / (2 * h)
        assert slope == pytest.approx(-(1 - e**2) * gamma0 * t0 / 3, rel=1e-8)
        # late times: T ~ t^-2
        late = hs_theory.haff_temperature(np.array([1e6, 2e6]), t0, e, gamma0)
        assert late[0] / late[1] == pytest.approx(4.0, rel=1e-4)
        # haff_time inverts it
        for fraction in (0.5, 1 / 3):
            tf = hs_theory.haff_time(fraction, e, gamma0)
            assert hs_theory.haff_temperature(tf, t0, e, gamma0) == pytest.approx(fraction * t0, rel=1e-12)


def test_haff_deviation_and_temperature():
    t0, e, gamma0 = 1.0, 0.9, 0.77
    times = np.array([0.0, 10.0, 20.0])
    haff = hs_theory.haff_temperature(times, t0, e, gamma0)
    rel, worst, at = cooling_runs.haff_deviation(times, haff * np.array([1.0, 0.97, 1.01]), t0, e, gamma0)
    assert rel == pytest.approx([0.0, -0.03, 0.01])
    assert worst == pytest.approx(0.03) and at == 10.0
    frame = dict(vel=np.array([[1.0, 0.0, 0.0], [0.0, -2.0, 0.0]]))
    assert cooling_runs.temperature(frame, np.array([1.0, 0.5])) == pytest.approx((1.0 + 0.5 * 4.0) / 6)


def test_shared_until_and_pair_summary():
    a = dict(times=[0, 1, 2, 3], T=[1.0, 0.9, 0.8, 0.7])
    b = dict(times=[0, 1, 2, 3], T=[1.0, 0.9001, 0.79, 0.7])
    assert cooling_report.shared_until(a, b) == 1
    assert cooling_report.shared_until(a, a) == 3
    pairs = [dict(speed=1.0, rel_error=x) for x in (0.001, -0.003)] + [dict(speed=0.3, rel_error=0.002)]
    s = cooling_runs.pair_summary(pairs)
    assert [x["speed"] for x in s] == [0.3, 1.0]
    assert s[1]["mean_rel_error"] == pytest.approx(-0.001) and s[1]["max_abs_rel_error"] == pytest.approx(0.003)


def test_pair_data_file(tmp_path):
    pairs = [(0.3, 0.01), (5.0, 0.2), (1.5, 0.05)]
    cooling_runs.write_pairs(tmp_path / "p.data", pairs, box=18.0)
    text = (tmp_path / "p.data").read_text()
    velocity_rows = text.split("Velocities")[1].split("\n")[2:8]
    assert all(len(row.split()) == 7 for row in velocity_rows)  # id vx vy vz wx wy wz
    d = read_data(tmp_path / "p.data")
    assert len(d.ids) == 6 and np.all(d.radius == 0.5) and d.mass == pytest.approx(np.ones(6))
    assert d.omega is not None and np.all(d.omega == 0)
    for k, (v, gap) in enumerate(pairs):
        a, b = 2 * k, 2 * k + 1
        assert d.pos[b, 0] - d.pos[a, 0] - 1.0 == pytest.approx(gap)
        assert d.vel[a, 0] - d.vel[b, 0] == pytest.approx(v)
        assert d.pos[a, 1:] == pytest.approx(d.pos[b, 1:])
    centres = d.pos[::2, 1:]
    assert min(np.linalg.norm(centres[i] - centres[j]) for i in range(3) for j in range(i)) >= 6.0
