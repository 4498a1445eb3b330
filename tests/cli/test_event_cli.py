"""`hardsphere run --engine event`: JSON contract, agreement of the keys with the stepper, bad input.
"""

import pytest

from hs_run import run, run_json

EVENT_KEYS = [
    "engine", "n", "packing_fraction", "box", "sim_time", "cells_per_dim", "scene_kernel", "precision",
    "loop_cpu_seconds", "collisions", "wall_collisions", "collision_rate_per_particle", "collision_rate_error",
    "kinetic_energy_initial", "kinetic_energy_final", "energy_rel_drift", "momentum_initial", "momentum_final",
    "temperature", "com_removed", "pair_virial", "compressibility_factor", "compressibility_factor_error",
    "pressure", "wall_pressure", "max_overlap", "speed_ks_distance", "speed_histogram", "seed",
    "collisions_per_second", "events_per_second", "events", "cell_crossings", "stale_events",
    "neighbour_list_rebuilds", "neighbour_shell",
]


def test_event_json_keys_and_physics(hs):
    j = run_json(hs, "--engine", "event", "--n", 500, "--phi", 0.3, "--time", 2, "--equilibrate-time", 0.5)
    for k in EVENT_KEYS:
        assert k in j, k
    assert j["engine"] == "event" and j["n"] == 500 and abs(j["sim_time"] - 2) < 1e-12
    assert abs(j["energy_rel_drift"]) < 1e-12 and j["max_overlap"] < 1e-10
    assert j["collisions"] > 1000 and j["collisions_per_second"] > 0 and j["events"] >= j["collisions"]


def test_same_data_file_same_result_and_walls(hs, tmp_path):
    data = tmp_path / "s.data"
    assert run(hs, "--n", 300, "--phi", 0.2, "--steps", 0, "--write-data", data).returncode == 0
    a = run_json(hs, "--engine", "event", "--read-data", data, "--time", 1)
    b = run_json(hs, "--engine", "event", "--read-data", data, "--time", 1)
    assert a["collisions"] == b["collisions"] and a["pair_virial"] == b["pair_virial"]
    walled = tmp_path / "w.data"
    assert run(hs, "--n", 300, "--phi", 0.2, "--boundary", "p,p,w", "--steps", 0, "--write-data", walled).returncode == 0
    w = run_json(hs, "--engine", "event", "--read-data", walled, "--boundary", "p,p,w", "--time", 1)
    assert w["wall_collisions"] > 0 and w["wall_pressure"][2] > 0 and w["wall_pressure"][0] is None


def test_stepper_time_option(hs):
    j = run_json(hs, "--n", 100, "--phi", 0.2, "--time", 0.5, "--dt", 0.01)
    assert j["steps"] == 50 and abs(j["sim_time"] - 0.5) < 1e-12


@pytest.mark.parametrize("args,needle", [
    (["--engine", "event", "--n", 100], "needs --time"),
    (["--engine", "event", "--n", 100, "--time", 1, "--steps", 5], "--steps is a stepper option"),
    (["--engine", "event", "--n", 100, "--time", 1, "--dt", 0.1], "--dt is a stepper option"),
    (["--engine", "event", "--n", 100, "--time", 1, "--detect", "sweep"], "--detect is a stepper option"),
    (["--engine", "event", "--n", 100, "--time", 1, "--precision", "float"], "double only"),
    (["--engine", "event", "--n", 100, "--time", -1], "time = -1"),
    (["--engine", "fast", "--n", 100, "--time", 1], "engine 'fast'"),
    (["--n", 100, "--time", 1, "--steps", 3], "give one"),
    (["--n", 100, "--blocks", 3], "--blocks is an event-engine option"),
    (["--engine", "event", "--n", 8, "--phi", 0.3, "--time", 1], "at least 3 cells"),
])
def test_event_bad_input(hs, tmp_path, args, needle):
    p = run(hs, *args, "--json", "out.json", cwd=tmp_path)
    assert p.returncode == 2, (p.returncode, p.stderr)
    assert needle in p.stderr, p.stderr
    assert not (tmp_path / "out.json").exists()
