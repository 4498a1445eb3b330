"""compare.rough_theory: the kinetic theory of rough inelastic hard spheres against a Monte Carlo of
the project's collision rule (Maxwellian pairs weighted by |g.n|), the Walton limits, the scaling
state and the ODEs. Fast (a few seconds); the engine runs are the ctest rough_hcs_quick."""
import math

import numpy as np
import pytest

from compare import rough_theory as rt

SAMPLES = 100000


def _pairs(rng, k=1000, r=0.7, q=0.4):
    inertia = q / 4
    v = rng.normal(size=(2, k, 3))
    w = rng.normal(0, math.sqrt(r / inertia), size=(2, k, 3))
    n = rng.normal(size=(k, 3))
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    return v, w, n


def _contact_velocity(v1, v2, w1, w2, n):
    return v1 - v2 - 0.5 * np.cross(w1 + w2, n)


@pytest.mark.parametrize("e,beta", [(0.9, 0.0), (0.9, 0.5), (0.7, 0.5), (0.95, -0.5), (1.0, 1.0), (0.5, -1.0)])
def test_collide_is_the_contract_rule(e, beta):
    v, w, n = _pairs(np.random.default_rng(11))
    v1, v2, w1, w2 = rt.collide(v[0], v[1], w[0], w[1], n, e, beta)
    g0, g1 = _contact_velocity(v[0], v[1], w[0], w[1], n), _contact_velocity(v1, v2, w1, w2, n)
    gn0, gn1 = (g0 * n).sum(axis=1), (g1 * n).sum(axis=1)
    assert gn1 == pytest.approx(-e * gn0, abs=1e-12)
    assert g1 - gn1[:, None] * n == pytest.approx(-beta * (g0 - gn0[:, None] * n), abs=1e-12)
    assert v1 + v2 == pytest.approx(v[0] + v[1], abs=1e-12)  # momentum
    # angular momentum about the contact point: I w_i + m (-a n) x v_i for each sphere
    inertia = 0.4 * 0.25
    for vi, wi, v0, w0, sign in ((v1, w1, v[0], w[0], 1), (v2, w2, v[1], w[1], -1)):
        l0 = inertia * w0 + np.cross(sign * 0.5 * n, v0)
        l1 = inertia * wi + np.cross(sign * 0.5 * n, vi)
        assert l1 == pytest.approx(l0, abs=1e-12)
    if beta == -1.0:
        assert w1 == pytest.approx(w[0], abs=1e-13) and w2 == pytest.approx(w[1], abs=1e-13)


def test_elastic_perfectly_rough_conserves_energy():
    v, w, n = _pairs(np.random.default_rng(5))
    v1, v2, w1, w2 = rt.collide(v[0], v[1], w[0], w[1], n, 1.0, 1.0)
    inertia = 0.1
    e0 = 0.5 * (v ** 2).sum(axis=(0, 2)) + 0.5 * inertia * (w ** 2).sum(axis=(0, 2))
    e1 = 0.5 * ((v1 ** 2).sum(axis=1) + (v2 ** 2).sum(axis=1)) + 0.5 * inertia * ((w1 ** 2).sum(axis=1)
                                                                                + (w2 ** 2).sum(axis=1))
    assert e1 == pytest.approx(e0, rel=1e-13)


@pytest.mark.parametrize("e,beta", [(0.9, 0.0), (0.9, 0.5), (0.7, 0.5), (0.95, -0.5), (0.8, 1.0)])
@pytest.mark.parametrize("r", [0.0, 0.4, 1.3])
def test_monte_carlo_energy_changes_give_the_coefficients(e, beta, r):
    a, b, c = rt.coefficients(e, beta)
    x = rt.energy_changes(SAMPLES, r, e, beta, rng=np.random.default_rng(int(100 * e + 10 * beta + r)))
    assert abs(x["tr"] + 4 * (a - b * r)) < 4.5 * x["tr_err"]
    assert abs(x["rot"] - 4 * (b - c * r)) < 4.5 * x["rot_err"] + 1e-12
    assert x["frequency"] == 1.0


def test_monte_carlo_detects_a_wrong_coefficient():
    # the test above can fail: the MC resolves the coefficients to a few percent
    a, b, c = rt.coefficients(0.9, 0.5)
    x = rt.energy_changes(SAMPLES, 1.0, 0.9, 0.5, rng=np.random.default_rng(2))
    assert abs(x["tr"] + 4 * (1.05 * a - b)) > 4.5 * x["tr_err"]
    assert abs(x["rot"] - 4 * (b - 1.05 * c)) > 4.5 * x["rot_err"]


def test_smooth_and_perfectly_rough_limits():
    a, b, c = rt.coefficients(0.8, -1.0)
    assert (a, b, c) == pytest.approx(((1 - 0.64) / 4, 0.0, 0.0))
    assert rt.scaling_ratio(0.8, -1.0) == math.inf
    # Haff: the smooth gas cools as dT/dt = -(1 - e^2) omega T / 3 whatever its rotation
    for r in (0.0, 1.0, 7.0):
        assert rt.constant_beta_rates(0.8, -1.0)(r)[0] / 3 == pytest.approx(-(1 - 0.64) / 3, rel=1e-14)
        assert rt.constant_beta_rates(0.8, -1.0)(r)[1] == 0.0
    # elastic, perfectly rough: equipartition, no cooling
    assert rt.scaling_ratio(1.0, 1.0) == pytest.approx(1.0, rel=1e-12)
    assert rt.cooling_rate(1.0, 1.0) == pytest.approx(0.0, abs=1e-15)
    q = 0.4
    assert rt.coefficients(1.0, 1.0, q) == pytest.approx((q / (1 + q) ** 2,) * 3)


@pytest.mark.parametrize("e,beta", [(0.9, 0.0), (0.9, 0.5), (0.7, 0.5), (0.95, -0.5)])
def test_scaling_state(e, beta):
    a, b, c = rt.coefficients(e, beta)
    r = rt.scaling_ratio(e, beta)
    assert r > 0 and b * r * r + (c - a) * r - b == pytest.approx(0.0, abs=1e-14)
    assert rt.ratio_of_rates(rt.constant_beta_rates(e, beta)) == pytest.approx(r, rel=1e-9)
    # the ODEs keep R from R(0) = R and approach it from R(0) = 1; T(t) = T0 / (1 + zeta0 t / 2)^2
    phi, t0 = 0.05, 1.3
    times = np.linspace(0, 40, 9)
    tt, tr = rt.temperatures(times, phi, t0, r, rt.constant_beta_rates(e, beta))
    assert tr / tt == pytest.approx(np.full(len(times), r), rel=1e-7)
    zeta0 = rt.cooling_rate(e, beta) * rt.collision_rate(phi, t0)
    assert tt == pytest.approx(t0 / (1 + zeta0 * times / 2) ** 2, rel=1e-7)
    tt, tr = rt.temperatures(np.geomspace(1, 1e7, 8), phi, t0, 1.0, rt.constant_beta_rates(e, beta))
    assert tr[-1] / tt[-1] == pytest.approx(r, rel=1e-4)
    third = rt.time_to_fraction(1 / 3, phi, t0, 1.0, rt.constant_beta_rates(e, beta))
    assert rt.temperatures([0, third], phi, t0, 1.0, rt.constant_beta_rates(e, beta))[0][1] == pytest.approx(t0 / 3)


def test_total_energy_balance_of_the_odes():
    # d(T + T_rot)/dt = -(4/3) omega [(A - B) T + (C - B) T_rot]: the dissipation is never negative
    for e, beta in [(0.9, 0.0), (1.0, 0.3), (0.7, 0.5)]:
        a, b, c = rt.coefficients(e, beta)
        for r in (0.0, 0.5, 2.0):
            assert (a - b) + (c - b) * r >= -1e-15


@pytest.mark.parametrize("mu_f,r", [(0.02, 0.1), (0.1, 1.0), (0.3, 0.5)])
def test_sliding_closed_form_against_monte_carlo(mu_f, r):
    e = 0.9
    h = rt.sliding_rates(e, mu_f)(r)
    x = rt.energy_changes(SAMPLES, r, e, 0.0, mu_f=mu_f, rng=np.random.default_rng(3), sliding_only=True)
    assert abs(x["tr"] - h[0]) < 4.5 * x["tr_err"]
    assert abs(x["rot"] - h[1]) < 4.5 * x["rot_err"]


def test_walton_limits():
    e, beta0 = 0.9, 0.5
    # huge mu: every contact sticks, the constant-beta rule
    const = rt.energy_changes(100000, 0.8, e, beta0, rng=np.random.default_rng(4))
    stick = rt.energy_changes(100000, 0.8, e, beta0, mu_f=1e12, rng=np.random.default_rng(4))
    assert stick["tr"] == pytest.approx(const["tr"], rel=1e-12) and stick["rot"] == pytest.approx(const["rot"], rel=1e-12)
    # small mu: (nearly) every contact slides
    x = rt.energy_changes(SAMPLES, 0.25, 0.95, beta0, mu_f=0.01, rng=np.random.default_rng(4))
    h = rt.sliding_rates(0.95, 0.01)(0.25)
    assert x["tr"] == pytest.approx(h[0], rel=0.01) and x["rot"] == pytest.approx(h[1], rel=0.02)
    # the Walton impulse never exceeds the constant-beta one: between the two limits
    v, w, n = _pairs(np.random.default_rng(8))
    for mu_f in (0.05, 0.3, 2.0):
        a = rt.collide(v[0], v[1], w[0], w[1], n, e, beta0, mu_f=mu_f)
        b = rt.collide(v[0], v[1], w[0], w[1], n, e, beta0)
        ja, jb = a[0] - v[0], b[0] - v[0]
        jna = (ja * n).sum(axis=1)
        assert (jna == pytest.approx((jb * n).sum(axis=1), rel=1e-12))
        jta = np.linalg.norm(ja - jna[:, None] * n, axis=1)
        assert np.all(jta <= np.linalg.norm(jb - (jb * n).sum(axis=1)[:, None] * n, axis=1) * (1 + 1e-12))
        assert np.all(jta <= mu_f * np.abs(jna) * (1 + 1e-12))


def test_walton_scaling_ratio_between_its_asymptotes():
    # large mu approaches the constant-beta0 ratio; small mu the sliding one (same samples throughout)
    def ratio(e, mu_f, **kw):
        return rt.ratio_of_rates(rt.sampled_rates(e, 0.5, mu_f=mu_f, samples=50000, **kw), 0.05, 2.0, 10)
    const = ratio(0.9, math.inf)
    assert const == pytest.approx(rt.scaling_ratio(0.9, 0.5), rel=0.03)  # the sampling's own error
    big = [ratio(0.9, mu) / const - 1 for mu in (1.0, 20.0)]
    assert -0.1 < big[0] < -0.01 and abs(big[1]) < 0.002
    small = [ratio(0.98, mu) / ratio(0.98, mu, sliding_only=True) - 1 for mu in (0.1, 0.03)]
    assert small[0] < -0.05 and abs(small[1]) < 0.03
    # too little friction at e = 0.9: the rotation cools more slowly than the translation, no scaling state
    assert rt.ratio_of_rates(rt.sliding_rates(0.9, 0.05)) is None


def test_cumulants_and_sonine_weights():
    rng = np.random.default_rng(9)
    k, inertia = 400000, 0.1
    mass = np.ones(k)
    v = rng.normal(size=(k, 3))
    w = rng.normal(0, math.sqrt(0.5 / inertia), size=(k, 3))
    a20, a02, a11 = rt.cumulants_of(v, w, mass, inertia)
    assert abs(a20) < 0.02 and abs(a02) < 0.02 and abs(a11) < 0.01
    tt, tr = rt.temperatures_of(v + 3.0, w, mass, inertia)  # the mean velocity is removed
    assert tt == pytest.approx(1.0, rel=0.01) and tr == pytest.approx(0.5, rel=0.01)
    # all speeds equal: c^4 = c^2^2, a20 = (4/15)(9/4) - 1 = -0.4
    u = v / np.linalg.norm(v, axis=1, keepdims=True)
    assert rt.cumulants_of(u, w, mass, inertia)[0] == pytest.approx(-0.4, abs=0.01)
    # smooth gas with a20: the collision frequency is (1 - a20/16) and the energy loss rate (1 + 3 a20/16) of
    # the Maxwellian ones, to first order (van Noije and Ernst)
    a = 0.05
    base = rt.energy_changes(SAMPLES, 1.0, 0.8, -1.0, rng=np.random.default_rng(6))
    corr = rt.energy_changes(SAMPLES, 1.0, 0.8, -1.0, rng=np.random.default_rng(6), cumulants=(a, 0.0, 0.0))
    assert corr["frequency"] == pytest.approx(1 - a / 16, abs=0.003)
    assert corr["tr"] * corr["frequency"] / base["tr"] == pytest.approx(1 + 3 * a / 16, abs=0.004)
