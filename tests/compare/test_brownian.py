"""compare.brownian's closed forms (compare.hard_sphere_theory.heavy_tracer) and its analysis:
Enskog's heavy-tracer D equals its
closure-free form at Enskog's collision rate, and the block analysis recovers D and the kinetic
temperature of an Ornstein-Uhlenbeck (Langevin) velocity with known D. The engine runs themselves
are the ctest brownian_quick (python3 -m compare.brownian --quick)."""
import math

import numpy as np
import pytest

from compare import brownian
from compare import hard_sphere_theory as hs_theory


def test_enskog_value_equals_its_closure_free_form_at_the_enskog_rate():
    th = hs_theory.heavy_tracer(0.05, 2453, 5.0, 125.0, 30.0, 1.0)
    assert th["D_enskog"] == pytest.approx(3 / (4 * th["mu"] * th["Gamma12_enskog"]), rel=1e-12)
    assert th["sigma12"] == 3.0 and th["mu"] == pytest.approx(125 / 126)
    assert th["momentum_factor"] == pytest.approx((1 - 125 / 2578) ** 2)
    assert 0 < th["D_stokes_einstein"] < th["D_enskog"]  # a dilute gas is far from the hydrodynamic limit


def langevin_run(rng, n, every, tau, m_big, kT):
    """Exact Ornstein-Uhlenbeck velocities sampled every `every`; positions integrated on a 20x
    finer grid (trapezoid)."""
    sub = 20
    h = every / sub
    a = math.exp(-h / tau)
    s = math.sqrt(kT / m_big * (1 - a * a))
    v = rng.normal(scale=math.sqrt(kT / m_big), size=3)
    x = np.zeros(3)
    rows = np.zeros((n, 8))
    for k in range(n):
        rows[k, 0], rows[k, 1:4], rows[k, 4:7] = k * every, x, v
        for _ in range(sub):
            v_new = a * v + s * rng.normal(size=3)
            x = x + 0.5 * h * (v + v_new)
            v = v_new
    rows[:, 7] = np.arange(n)  # one collision per sample interval
    return rows


def test_block_analysis_recovers_a_langevin_diffusion_coefficient():
    rng = np.random.default_rng(5)
    m_big, kT, tau = 50.0, 1.0, 4.0
    d_true = kT * tau / m_big
    runs = [{"rows": langevin_run(rng, 4000, brownian.SAMPLE_EVERY, tau, m_big, kT), "kT": kT,
             "summary": {"loop_cpu_seconds": 0.0}} for _ in range(4)]
    th = {"tau": tau, "mu": 1.0, "momentum_factor": 1.0, "n_small": 1e12, "D_enskog": d_true,
          "Gamma12_enskog": 2.0, "g12": 1.0}
    res = brownian.analyse(runs, m_big, kT, th)
    assert res["blocks"] >= 40
    assert abs(res["D"] - d_true) < 4 * res["D_err"] and res["D_err"] < 0.1 * d_true
    assert abs(res["T_big_ratio"] - 1) < 4 * res["T_big_ratio_err"] and res["T_big_ratio_err"] < 0.05
    assert res["Gamma12"] == pytest.approx(1 / brownian.SAMPLE_EVERY)
    whole = brownian.analyse(runs, m_big, kT, th, whole_runs=True)  # --quick's one block per run
    assert whole["blocks"] == 4 and abs(whole["D"] - d_true) < 4 * whole["D_err"]
