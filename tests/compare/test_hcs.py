"""compare.hcs: the Sonine coefficient of the homogeneous cooling state (quick mode, e = 0.5),
and its theory function (compare.hard_sphere_theory.a2_van_noije_ernst)."""
import json
import subprocess
import sys

import pytest

from compare import hard_sphere_theory as hs_theory
from compare import hcs


def test_van_noije_ernst_limits():
    assert hs_theory.a2_van_noije_ernst(1.0) == 0.0  # elastic: Maxwell-Boltzmann
    assert hs_theory.a2_van_noije_ernst(1 / 2 ** 0.5) == pytest.approx(0.0, abs=1e-15)  # sign change at e^2 = 1/2
    assert hs_theory.a2_van_noije_ernst(0.5) == pytest.approx(16 * 0.5 * 0.5 / (81 - 8.5 + 3.75))


def test_a2_is_zero_for_maxwell_boltzmann_and_not_for_one_speed():
    # Over 100 seeds a2 of 200000 Maxwell-Boltzmann velocities had sd 0.0017: 0.01 is 6 sd.
    rng = __import__("numpy").random.default_rng(3)
    assert hcs.a2_of(rng.normal(size=(200000, 3))) == pytest.approx(0.0, abs=0.01)
    v = rng.normal(size=(200000, 3))
    v /= __import__("numpy").linalg.norm(v, axis=1)[:, None]  # all speeds 1: <c^4> = <c^2>^2
    assert hcs.a2_of(v) == pytest.approx(-0.4, abs=0.01)


def test_cooling_state_matches_van_noije_ernst(hs, tmp_path):
    p = subprocess.run([sys.executable, "-m", "compare.hcs", "--hardsphere", hs, "--out", str(tmp_path),
                        "--quick"], capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stdout + p.stderr
    row = json.loads((tmp_path / "hcs.json").read_text())["rows"][0]
    assert row["e"] == 0.5 and abs(row["a2"] - row["a2_theory"]) < 4 * row["a2_err"] + 0.01
    assert (tmp_path / "hcs_a2.png").stat().st_size > 10000
