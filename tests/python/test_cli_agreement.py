"""A Python run equals the CLI's run of the same data file bit for bit: counters, Z, pressure,
energies and the final state (docs/python.md#agreement-with-the-cli)."""
import json

import numpy as np
import pytest

import hardsphere as hs

# The summary keys that are physics (the rest are CPU times and engine bookkeeping).
KEYS = ["n", "collisions", "wall_collisions", "compressibility_factor", "pressure", "wall_pressure", "temperature",
        "collision_rate_per_particle", "kinetic_energy_initial", "kinetic_energy_final", "energy_rel_drift",
        "momentum_initial", "momentum_final", "pair_virial", "max_overlap", "speed_ks_distance", "speed_histogram",
        "sim_time", "potential_energy_initial", "potential_energy_final", "dissipated_energy", "restitution",
        "contact_time", "gravity", "packing_fraction", "box", "cells_per_dim", "scene_kernel", "warnings",
        # the event engine's block error bars (run(..., blocks=20) as --blocks 20)
        "blocks", "compressibility_factor_error", "collision_rate_error"]


def compare(sim, summary, cli_data, boundary):
    o = sim.observables()
    for k in KEYS:
        assert (k in o) == (k in summary), k
        if k in summary:
            assert o[k] == summary[k], k
    final = hs.System.from_data(str(cli_data), boundary=boundary)
    for f in ("ids", "positions", "velocities", "images"):
        assert np.array_equal(getattr(final, f), getattr(sim, f)), f


@pytest.fixture(scope="module")
def gas(tmp_path_factory):
    path = tmp_path_factory.mktemp("gas") / "start.data"
    hs.System.random(n=600, phi=0.25, seed=7).write_data(str(path))
    return path


@pytest.fixture(scope="module")
def bed(tmp_path_factory):
    path = tmp_path_factory.mktemp("bed") / "bed.data"
    hs.System.random(n=400, box=(8, 8, 16), boundary="p,p,w", seed=3).write_data(str(path))
    return path


@pytest.mark.parametrize("chunked", [False, True])
def test_stepper_equals_cli(cli, gas, tmp_path, chunked):
    out = tmp_path / "cli.data"
    summary = json.loads(cli("run", "--read-data", gas, "--steps", 400, "--dt", 0.01, "--json", "-",
                             "--write-data", out).stdout)
    sim = hs.Stepper(hs.System.from_data(str(gas)), dt=0.01)
    if chunked:  # a callback splits the run; the result is the same
        sim.run(steps=400, callback=lambda s: None, every=37)
    else:
        sim.run(time=4.0)
    assert sim.steps == 400
    compare(sim, summary, out, "p")


def test_stepper_walls_gravity_restitution_equal_cli(cli, bed, tmp_path):
    out = tmp_path / "cli.data"
    summary = json.loads(cli("run", "--read-data", bed, "--boundary", "p,p,w", "--gravity", "0,0,-1",
                             "--restitution", 0.9, "--detect", "sweep", "--steps", 300, "--dt", 0.005,
                             "--json", "-", "--write-data", out).stdout)
    sim = hs.Stepper(hs.System.from_data(str(bed), boundary="p,p,w"), dt=0.005, gravity=(0, 0, -1),
                     restitution=0.9, detect="sweep")
    sim.run(steps=300)
    compare(sim, summary, out, "p,p,w")


def test_stepper_warnings_equal_cli(cli, gas, tmp_path):
    """Long steps with overlap detection: the CLI's warning, word for word."""
    out = tmp_path / "cli.data"
    summary = json.loads(cli("run", "--read-data", gas, "--detect", "overlap", "--steps", 20, "--dt", 0.1,
                             "--json", "-", "--write-data", out).stdout)
    assert summary["warnings"] and summary["warnings"][-1].startswith("--detect overlap with steps")
    sim = hs.Stepper(hs.System.from_data(str(gas)), dt=0.1, detect="overlap")
    sim.run(steps=20)
    compare(sim, summary, out, "p")


@pytest.mark.parametrize("blocks", [7, 1])
def test_event_engine_blocks_equal_cli(cli, gas, tmp_path, blocks):
    """--blocks B and run(blocks=B), split by callbacks or not: the same error bars."""
    out = tmp_path / "cli.data"
    summary = json.loads(cli("run", "--read-data", gas, "--engine", "event", "--time", 1.7, "--blocks", blocks,
                             "--json", "-", "--write-data", out).stdout)
    assert summary["blocks"] == blocks and (summary["compressibility_factor_error"] > 0) == (blocks > 1)
    sim = hs.EventEngine(hs.System.from_data(str(gas)))
    sim.run(time=1.7, blocks=blocks, callback=lambda s: None, every=0.13)
    compare(sim, summary, out, "p")


@pytest.mark.parametrize("every", [None, 0.3, 1.1])
def test_event_engine_equals_cli(cli, gas, tmp_path, every):
    out = tmp_path / "cli.data"
    summary = json.loads(cli("run", "--read-data", gas, "--engine", "event", "--time", 2.5, "--json", "-",
                             "--write-data", out).stdout)
    sim = hs.EventEngine(hs.System.from_data(str(gas)))
    sim.run(time=2.5, callback=(lambda s: None) if every else None, every=every)
    assert sim.time == 2.5
    compare(sim, summary, out, "p")


def test_event_engine_walls_gravity_equal_cli(cli, bed, tmp_path):
    out = tmp_path / "cli.data"
    summary = json.loads(cli("run", "--read-data", bed, "--boundary", "p,p,w", "--gravity", "0,0,-1",
                             "--engine", "event", "--time", 1.5, "--json", "-", "--write-data", out).stdout)
    sim = hs.EventEngine(hs.System.from_data(str(bed), boundary="p,p,w"), gravity=(0, 0, -1))
    sim.run(time=1.5)
    compare(sim, summary, out, "p,p,w")


def test_generated_state_equals_cli(cli, tmp_path):
    """System.random is the CLI's --init random: same state, same summary (com_removed, seed)."""
    out = tmp_path / "cli.data"
    summary = json.loads(cli("run", "--n", 300, "--phi", 0.2, "--init", "random", "--seed", 5, "--steps", 100,
                             "--json", "-", "--write-data", out).stdout)
    sim = hs.Stepper(hs.System.random(n=300, phi=0.2, seed=5, method="random"))
    sim.run(steps=100)
    o = sim.observables()
    assert o["com_removed"] is True and o["seed"] == 5
    compare(sim, summary, out, "p")


def test_two_runs_equal_one(gas):
    a = hs.Stepper(hs.System.from_data(str(gas)))
    a.run(steps=150)
    b = hs.Stepper(hs.System.from_data(str(gas)))
    b.run(steps=100)
    b.run(steps=50)
    assert a.observables()["collisions"] == b.observables()["collisions"]
    assert np.array_equal(a.positions, b.positions)


ROUGH_KEYS = ["tangential_restitution", "friction", "inertia", "temperature_translational_initial",
              "temperature_translational_final", "temperature_rotational_initial", "temperature_rotational_final",
              "kinetic_energy_translational_initial", "kinetic_energy_translational_final",
              "kinetic_energy_rotational_initial", "kinetic_energy_rotational_final", "dissipated_energy_normal",
              "dissipated_energy_tangential"]


@pytest.mark.parametrize("engine", ["stepper", "event"])
def test_rough_spheres_equal_cli(cli, tmp_path, engine):
    """Rough spheres: the keywords are the CLI's options, the omegas come from the data file and the
    summary (rough keys included) and the final omegas equal the CLI's bit for bit."""
    start = tmp_path / "rough.data"
    s = hs.System.random(n=400, phi=0.25, seed=4, rotational_temperature=1.5)
    assert s.omegas.shape == (400, 3) and s.omegas.any()
    s.write_data(str(start))
    out = tmp_path / "cli.data"
    rough = ["--tangential-restitution", 0.4, "--friction", 0.3, "--restitution", 0.9, "--inertia", 0.35]
    length = ["--steps", 200] if engine == "stepper" else ["--engine", "event", "--time", 2.0]
    summary = json.loads(cli("run", "--read-data", start, *length, *rough, "--json", "-", "--write-data", out).stdout)
    keywords = dict(tangential_restitution=0.4, friction=0.3, restitution=0.9, inertia=0.35)
    sim = (hs.Stepper(hs.System.from_data(str(start)), dt=0.01, **keywords) if engine == "stepper"
           else hs.EventEngine(hs.System.from_data(str(start)), **keywords))
    sim.run(steps=200) if engine == "stepper" else sim.run(time=2.0)
    compare(sim, summary, out, "p")
    o = sim.observables()
    for k in ROUGH_KEYS:
        assert o[k] == summary[k], k
    assert np.array_equal(hs.System.from_data(str(out)).omegas, sim.omegas)
    assert not hs.Stepper(hs.System.from_data(str(start))).observables().keys() & set(ROUGH_KEYS)


WALL_KEYS = ["wall_laws", "wall_dissipated_energy_normal", "wall_dissipated_energy_tangential",
             "dissipated_energy_normal", "dissipated_energy_tangential"]


@pytest.mark.parametrize("engine", ["stepper", "event"])
def test_wall_laws_equal_cli(cli, bed, tmp_path, engine):
    """The wall keywords are the CLI's options: text, one number or a dict give the same run."""
    out = tmp_path / "cli.data"
    length = ["--steps", 300, "--dt", 0.005] if engine == "stepper" else ["--engine", "event", "--time", 1.5]
    summary = json.loads(cli("run", "--read-data", bed, "--boundary", "p,p,w", "--gravity", "0,0,-1",
                             "--tangential-restitution", 0.5, "--wall-restitution", "zlo=0.5,zhi=0.8",
                             "--wall-tangential-restitution", 0, "--wall-friction", "zlo=0.3", *length,
                             "--json", "-", "--write-data", out).stdout)
    system = hs.System.from_data(str(bed), boundary="p,p,w")
    laws = dict(gravity=(0, 0, -1), tangential_restitution=0.5, wall_restitution={"zlo": 0.5, "zhi": 0.8},
                wall_tangential_restitution=0, wall_friction="zlo=0.3")
    sim = hs.Stepper(system, dt=0.005, **laws) if engine == "stepper" else hs.EventEngine(system, **laws)
    sim.run(steps=300) if engine == "stepper" else sim.run(time=1.5)
    compare(sim, summary, out, "p,p,w")
    o = sim.observables()
    assert summary["wall_dissipated_energy_normal"] > 0
    for k in WALL_KEYS:
        assert o[k] == summary[k], k


@pytest.mark.parametrize("kwargs,needle", [
    (dict(wall_restitution=1.5), "wall_restitution 1.5 must be in (0, 1]"),
    (dict(wall_restitution={"zlo": 0}), "wall_restitution zlo=0 must be in (0, 1]"),
    (dict(wall_restitution={"bottom": 0.5}), "unknown face 'bottom'"),
    (dict(wall_restitution="xlo=0.5"), "no wall at xlo"),
    (dict(wall_restitution=True), "wall_restitution takes a number"),
    (dict(wall_friction=0.3), "wall_friction 0.3 needs rough spheres"),
])
def test_bad_wall_keywords_are_value_errors(bed, kwargs, needle):
    system = hs.System.from_data(str(bed), boundary="p,p,w")
    for engine in (hs.Stepper, hs.EventEngine):
        with pytest.raises(ValueError, match=needle.replace("(", r"\(").replace(")", r"\)").replace("[", r"\[")):
            engine(system, **kwargs)
