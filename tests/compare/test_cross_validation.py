"""The cross-validation's own measuring code on cases with known answers (compare.hard_sphere_theory,
compare.crossval.observables, the stiffness mapping of compare.crossval.plan)."""
import math

import numpy as np
import pytest

from compare import hard_sphere_theory as hs_theory
from compare.crossval import observables as obs
from compare.crossval import plan as xv_plan

MONO = [(1.0, 1.0, 1.0)]


@pytest.mark.parametrize("phi", [0.1, 0.3, 0.45])
def test_one_species_mixture_formulas_are_carnahan_starling_and_enskog(phi):
    assert hs_theory.z_bmcsl(phi, MONO) == pytest.approx(hs_theory.z_carnahan_starling(phi), rel=1e-14)
    g = hs_theory.contact_value(phi, MONO, 0, 0)
    assert g == pytest.approx((1 - phi / 2) / (1 - phi) ** 3, rel=1e-14)
    z_cs = hs_theory.z_carnahan_starling(phi)
    assert hs_theory.enskog_rate(phi, MONO) == pytest.approx(hs_theory.enskog_rate_from_z(phi, z_cs), rel=1e-12)


def test_bmcsl_of_equal_species_is_the_one_species_value():
    two = [(0.3, 1.0, 1.0), (0.7, 1.0, 1.0)]
    assert hs_theory.z_bmcsl(0.4, two) == pytest.approx(hs_theory.z_bmcsl(0.4, MONO), rel=1e-14)
    assert hs_theory.enskog_rate(0.4, two) == pytest.approx(hs_theory.enskog_rate(0.4, MONO), rel=1e-14)
    # Z - 1 = (2 pi n / 3) sum x_i x_j sigma_ij^3 g_ij, the virial route from the contact values
    mix = [(0.5, 1.0, 1.0), (0.5, 1.4, 1.4**3)]
    n = hs_theory.density_at(0.3, mix)
    virial = sum(xi * xj * ((di + dj) / 2) ** 3 * hs_theory.contact_value(0.3, mix, i, j)
                 for i, (xi, di, _) in enumerate(mix) for j, (xj, dj, _) in enumerate(mix))
    assert 1 + 2 * math.pi * n / 3 * virial == pytest.approx(hs_theory.z_bmcsl(0.3, mix), rel=1e-12)


def _frames(pos, times, box=10.0, vel=None):
    n = pos.shape[1]
    return [dict(t=t, lo=np.zeros(3), hi=np.full(3, box), ids=np.arange(1, n + 1), types=np.ones(n, int),
                 radius=np.full(n, 0.5), pos=p, vel=None if vel is None else vel[k], unwrapped=False)
            for k, (t, p) in enumerate(zip(times, pos))]


def test_diffusion_of_a_random_walk_through_periodic_wrapping():
    rng = np.random.default_rng(3)
    n, nf, dt, d_true = 4000, 41, 0.05, 0.2
    steps = rng.normal(0, math.sqrt(2 * d_true * dt), (nf - 1, n, 3))
    pos = np.concatenate([rng.uniform(0, 10, (1, n, 3)), np.zeros((nf - 1, n, 3))])
    pos[1:] = pos[0] + np.cumsum(steps, axis=0)
    wrapped = np.mod(pos, 10.0)
    _, _, d, err = obs.msd_diffusion(_frames(wrapped, dt * np.arange(nf)), (0.5, 1.0))
    assert d == pytest.approx(d_true, abs=4 * err)
    assert err < 0.02 * d_true
    assert obs.msd_diffusion(_frames(wrapped, dt * np.arange(nf)), (5.0, 9.0))[2] is None  # window past the run


def test_rdf_of_an_ideal_gas_is_one_and_contact_fit_finds_a_linear_g():
    rng = np.random.default_rng(5)
    frames = _frames(rng.uniform(0, 12, (4, 6000, 3)), [0, 1, 2, 3], box=12.0)
    r, g, counts = obs.rdf(frames, rmax=3.0, width=0.05)["all"]
    sel = r > 1
    assert np.abs(g[sel] - 1).max() < 5 * (1 / np.sqrt(counts[sel])).max()
    rr = np.linspace(0.005, 1.995, 200)
    value, err = obs.contact_value(rr, 2.5 - 3 * (rr - 1), np.full(200, 1e6), 1.0)
    assert value == pytest.approx(2.5, abs=1e-9)


def test_speeds_ks_accepts_maxwell_boltzmann_and_rejects_one_speed():
    rng = np.random.default_rng(7)
    v = rng.normal(0, 1.3, (1, 5000, 3))
    f = _frames(np.zeros((1, 5000, 3)), [0], vel=v)[0]
    _, p, temperature = obs.speed_ks(f, np.ones(5000))
    # Over 200 seeds p was 0.15 or more (T is fitted: the test is conservative) and T / 1.69 - 1
    # had sd 1.23%: p above 6e-5 (the two-sided 4-sigma tail), T within 4 sd, rounded up.
    assert p > 6e-5 and temperature == pytest.approx(1.69, rel=0.06)
    directions = v[0] / np.linalg.norm(v[0], axis=1)[:, None]
    f["vel"] = directions
    assert obs.speed_ks(f, np.ones(5000))[1] < 1e-10


def test_contacts_started_counts_each_new_pair_once():
    # two spheres approach, touch for three frames, separate, touch again: two contacts
    x = [3.0, 1.5, 0.9, 0.8, 0.9, 1.5, 0.95, 2.0]
    pos = np.array([[[1.0, 1, 1], [1.0 + d, 1, 1]] for d in x])
    started, elapsed = obs.contacts_started(iter(_frames(pos, np.arange(len(x)))))
    assert (started, elapsed) == (2, len(x) - 1)


@pytest.mark.parametrize("engine", xv_plan.SOFT_ENGINES)
def test_stiffness_for_a_shift_gives_that_shift(engine):
    for shift in (0.04, 0.005, 0.00125):
        k = xv_plan.stiffness_for_shift(engine, shift)
        assert xv_plan.bh_shift(engine, k) == pytest.approx(shift, rel=1e-9)
