"""compare.rough_cooling_soft's beta0 rule for the linear soft contact: a sticking contact's
tangential contact velocity, integrated with the project's collision geometry, against
-cos(omega_t t_c). The runs themselves are python3 -m compare.rough_cooling_soft (not a ctest)."""
import math

import numpy as np
import pytest
from scipy import integrate

from compare import rough_cooling_soft as rcs
from compare import soft_spheres as soft


def _sticking_contact(kn, gamman, kt, meff, q, v=1.0):
    """Integrates the normal damped spring and the tangential spring of the relative contact
    displacement xi (mass meff q / (1 + q)) from touch to separation: g_t(end) / g_t(0)."""
    mt = meff * q / (1 + q)

    def rhs(t, y):
        d, dv, xi, xv = y
        return [dv, -kn / meff * d - gamman * dv, xv, -kt / mt * xi]

    def leave(t, y):
        return y[0]
    leave.terminal, leave.direction = True, -1
    sol = integrate.solve_ivp(rhs, (0, 10.0), [0.0, v, 0.0, 0.01], events=leave, rtol=1e-10, atol=1e-13,
                              first_step=1e-9, max_step=1e-3)
    return sol.y[3, -1] / 0.01


@pytest.mark.parametrize("ratio", [0.01, 0.05, 1 / 14, 2 / 7, 0.5])
@pytest.mark.parametrize("e", [0.9, 0.7])
def test_linear_beta0_rule(ratio, e):
    kn, meff = 1.0e4, 0.5
    gamman = soft.gamman_for_restitution(e, kn, meff)
    s = dict(kn=kn, gamman=gamman, kt=ratio * kn, contact_time=soft.hooke_contact_time(gamman, kn, meff))
    assert rcs.beta0_linear(s) == pytest.approx(-_sticking_contact(kn, gamman, ratio * kn, meff, 0.4), abs=1e-7)


def test_kt_two_sevenths_reverses_the_tangential_velocity():
    s = rcs.settings("lammps", 0.01)
    assert s["kt"] == pytest.approx(2 / 7 * s["kn"])
    assert rcs.beta0_linear(s) == pytest.approx(1.0, abs=1e-4)
    assert rcs.beta0_linear(dict(s, kt=1e-9 * s["kn"])) == pytest.approx(-1.0, abs=1e-6)
    assert s["dt"] == pytest.approx(s["contact_time"] / rcs.STEPS_PER_CONTACT)
    assert np.isfinite(s["gamman"]) and math.exp(-s["gamman"] * s["contact_time"] / 2) == pytest.approx(rcs.E)
