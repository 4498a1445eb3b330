"""compare.hard_sphere_theory.enskog_transport: the dilute limit is Chapman-Enskog's with the
converged Sonine factors, and at n = 0.5 the values the report compares with."""
import math

import pytest

from compare import hard_sphere_theory as hs_theory


def test_dilute_limit_is_chapman_enskog():
    phi = 1e-9
    th = hs_theory.enskog_transport(phi)
    n = 6 * phi / math.pi
    assert th["D"] * n == pytest.approx(1.01896 * 3 / 8 / math.sqrt(math.pi), rel=1e-8)
    assert th["eta"] == pytest.approx(1.016 * 5 / 16 / math.sqrt(math.pi), rel=1e-8)
    assert th["lam"] == pytest.approx(1.02513 * 75 / 64 / math.sqrt(math.pi), rel=1e-8)
    assert th["lam"] / th["eta"] == pytest.approx(15 / 4 * 1.02513 / 1.016)  # Eucken's ratio, k = m = 1


def test_values_at_n_one_half():
    phi = math.pi / 12  # n = 0.5
    th = hs_theory.enskog_transport(phi)
    g = (1 - phi / 2) / (1 - phi) ** 3
    assert th["g"] == pytest.approx(g)
    assert th["D"] == pytest.approx(1.01896 * 3 / (8 * 0.5 * g * math.sqrt(math.pi)))
    # the project's older helper (eta only) agrees
    assert th["eta"] == pytest.approx(hs_theory.enskog_viscosity(0.5), rel=1e-12)
    assert 0.5 < th["eta"] < 0.6 and 2.2 < th["lam"] < 2.6
