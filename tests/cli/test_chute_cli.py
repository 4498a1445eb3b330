"""A sphere on an inclined plane made by tilted gravity over a floor (x periodic, walls on z,
g = (sin t, 0, -cos t)), through the command line in both engines, against the analytic results
(the unit tests' Chute cases hold the derivations): frictionless, a = g sin t to rounding; rough
(beta0 0, mu 0.1, q 2/5) above the rolling limit tan t > mu (1 + q) / q, sliding at g (sin t - mu
cos t); below it rolling at g sin t / (1 + q). The rough cases are within one resting contact's
hop: |v_x - a T| <= g sin(t) tau (tau: the stepper's dt 0.01, the event engine's resting time
0.01 sqrt(d / g) = 0.01)."""
import math

import pytest
from compare.lammps_files import read_data, spheres, write_data
from hs_run import run

T = 10.0
ROUGH = ("--tangential-restitution", 0, "--friction", 0.1)


def final_vx(hs, tmp_path, tilt, engine, *physics):
    start, end = tmp_path / "start.data", tmp_path / "end.data"
    write_data(start, spheres([[2.0, 5.0, 0.5]], [[0, 0, 0]], box=[[0, 10], [0, 10], [0, 10]], mass=1.0))
    p = run(hs, "--read-data", start, "--boundary", "p,p,w", "--gravity", f"{math.sin(tilt)!r},0,{-math.cos(tilt)!r}",
            *engine, *physics, "--write-data", end, "--quiet")
    assert p.returncode == 0, p.stderr
    return read_data(end).vel[0][0], p.stderr


ENGINES = [("--steps", 1000, "--dt", 0.01), ("--engine", "event", "--time", T)]


@pytest.mark.parametrize("engine", ENGINES)
def test_smooth_sphere_on_a_frictionless_incline(hs, tmp_path, engine):
    vx, err = final_vx(hs, tmp_path, 0.5, engine)
    assert vx == pytest.approx(math.sin(0.5) * T, rel=1e-12)
    assert "with no frictional wall" in err  # nothing brakes it: the run says so


@pytest.mark.parametrize("engine", ENGINES)
def test_rough_sphere_slides_above_the_rolling_limit(hs, tmp_path, engine):
    vx, err = final_vx(hs, tmp_path, 0.5, engine, *ROUGH)
    assert vx == pytest.approx((math.sin(0.5) - 0.1 * math.cos(0.5)) * T, abs=math.sin(0.5) * 0.01)
    assert "warning" not in err


@pytest.mark.parametrize("engine", ENGINES)
def test_rough_sphere_rolls_below_the_rolling_limit(hs, tmp_path, engine):
    vx, _ = final_vx(hs, tmp_path, 0.2, engine, *ROUGH)
    assert vx == pytest.approx(math.sin(0.2) / 1.4 * T, abs=math.sin(0.2) * 0.01)
