"""Shaped walls in Python (walls=[...], the CLI's --wall words): a drum run equals the CLI's run
of the same data file bit for bit, wall totals included; System.random places spheres clear of
the walls; bad walls raise ValueError with the CLI's message."""
import json

import numpy as np
import pytest

import hardsphere as hs

DRUM = "cylinder y 10 10 8 rotate 0.5 restitution 0.6 tangential_restitution 0.2 friction 0.5"
PHYSICS = dict(dt=0.005, gravity=(0, 0, -1), restitution=0.7, tangential_restitution=0.3)


def test_random_states_start_clear_of_the_walls():
    s = hs.System.random(n=120, box=(20, 20, 20), boundary="w", seed=3, walls=[DRUM, "sphere 10 10 10 1 outside"])
    rho = np.hypot(s.positions[:, 0] - 10, s.positions[:, 2] - 10)
    assert rho.max() <= 7.5
    assert np.linalg.norm(s.positions - 10, axis=1).min() >= 1.5


def test_a_drum_equals_the_cli_run(cli, tmp_path):
    start = tmp_path / "start.data"
    hs.System.random(n=120, box=(20, 20, 20), boundary="w", seed=3, walls=[DRUM]).write_data(str(start))
    out = tmp_path / "cli.json"
    cli("run", "--read-data", start, "--boundary", "w", "--steps", 800, "--dt", 0.005, "--gravity", "0,0,-1",
        "--restitution", 0.7, "--tangential-restitution", 0.3, "--wall", DRUM, "--json", out)
    summary = json.loads(out.read_text())
    sim = hs.Stepper(hs.System.from_data(str(start), boundary="w"), walls=[DRUM], **PHYSICS)
    sim.run(steps=800)
    o = sim.observables()
    for k in ("shaped_walls", "wall_work", "collisions", "wall_collisions", "resting_contacts", "kinetic_energy_final",
              "potential_energy_final", "wall_dissipated_energy_normal", "wall_dissipated_energy_tangential"):
        assert o[k] == summary[k], k
    assert o["shaped_walls"][0]["work"] > 0


@pytest.mark.parametrize("walls,says", [
    ("sphere 1 1 1 1", "walls must be a list of wall specs"),
    ([3], "walls: each wall is a spec string, got 3"),
    (["sphere 10 10 10 0"], "walls 'sphere 10 10 10 0': radius 0 must be > 0"),
    (["cone z 10 10 2 5 0 0"], "radii 0 0 must be >= 0 and not both 0"),
])
def test_bad_walls_raise_value_error(walls, says):
    s = hs.System.random(n=10, box=(20, 20, 20), boundary="w", seed=1)
    with pytest.raises(ValueError, match=None) as e:
        hs.Stepper(s, walls=walls)
    assert says in str(e.value)


def test_the_event_engine_refuses_shaped_walls():
    s = hs.System.random(n=10, box=(20, 20, 20), boundary="w", seed=1)
    with pytest.raises(ValueError, match="shaped walls run in the stepper only"):
        hs.EventEngine(s, walls=["sphere 10 10 10 1 outside"])


PLATE = "plane 0 0 1 0 0 1 wiggle z 0.5 3 restitution 0.9"


def test_a_wiggled_bed_equals_the_cli_run_and_its_clock_runs_on(cli, tmp_path):
    # A vibrated bed (wiggle, the CLI's words): the CLI's run bit for bit; two run() calls of one
    # Stepper equal one run of their sum (the wall's time runs on between them).
    start = tmp_path / "start.data"
    hs.System.random(n=100, box=(10, 10, 12), boundary="p,p,w", seed=3, walls=[PLATE]).write_data(str(start))
    out = tmp_path / "cli.json"
    cli("run", "--read-data", start, "--boundary", "p,p,w", "--steps", 600, "--dt", 0.005, "--gravity", "0,0,-1",
        "--restitution", 0.7, "--tangential-restitution", 0.3, "--wall", PLATE, "--json", out)
    summary = json.loads(out.read_text())
    system = hs.System.from_data(str(start), boundary="p,p,w")
    sim = hs.Stepper(system, walls=[PLATE], **PHYSICS)
    sim.run(steps=600)
    split = hs.Stepper(system, walls=[PLATE], **PHYSICS)
    split.run(steps=250)
    split.run(steps=350)
    o = sim.observables()
    for k in ("shaped_walls", "wall_work", "collisions", "wall_collisions", "resting_contacts", "kinetic_energy_final"):
        assert o[k] == summary[k], k
    assert o["shaped_walls"][0]["work"] > 0
    np.testing.assert_array_equal(split.positions, sim.positions)
