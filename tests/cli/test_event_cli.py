"""`hardsphere run --engine event`: JSON contract, agreement of the keys with the stepper, bad input.
"""
import math

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
    assert j["collisions"] > 1000 and j["events"] >= j["collisions"]
    # rates from the measured CPU time: present and non-negative, never compared with anything
    assert all(math.isfinite(j[k]) and j[k] >= 0 for k in ("collisions_per_second", "events_per_second",
                                                           "loop_cpu_seconds"))


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


def big_sphere_data(path, length, big=1):
    """`big` spheres of diameter 10 (mass 1000) and 16 unit spheres in a periodic box of
    length x 20 x 20."""
    atoms = [(10.0, 1000.0, length / 2 - 5 * k, 5.0 + 10 * k, 10.0) for k in range(big)]
    atoms += [(1.0, 1.0, 0.5, y, z) for y in (1.0, 3.0, 17.0, 19.0) for z in (1.0, 3.0, 17.0, 19.0)]
    lines = ["big spheres", "", f"{len(atoms)} atoms", "2 atom types", "",
             f"0 {length} xlo xhi", "0 20 ylo yhi", "0 20 zlo zhi", "", "Atoms # sphere", ""]
    for i, (d, m, x, y, z) in enumerate(atoms):
        lines.append(f"{i + 1} {2 if d > 1 else 1} {d} {m / (3.141592653589793 / 6 * d ** 3)!r} {x} {y} {z}")
    lines += ["", "Velocities", ""]
    lines += [f"{i + 1} {0.01 if i < big else 1} {0.3 * (i % 3 - 1)} {0.2 * (i % 2)}" for i in range(len(atoms))]
    path.write_text("\n".join(lines) + "\n")


def test_event_big_sphere_box_rules(hs, tmp_path):
    # Big spheres do not size the cells: a periodic axis shorter than three big diameters runs
    # if it is longer than twice the largest contact distance plus a shell (one big sphere:
    # 2 x 5.5); with two big spheres 20 is not.
    ok, short = tmp_path / "ok.data", tmp_path / "short.data"
    big_sphere_data(ok, 21.0)
    big_sphere_data(short, 20.0, big=2)
    j = run_json(hs, "--engine", "event", "--read-data", ok, "--time", 5)
    assert j["collisions"] > 0 and abs(j["energy_rel_drift"]) < 1e-12 and j["max_overlap"] < 1e-10
    p = run(hs, "--engine", "event", "--read-data", short, "--time", 1, "--json", "out.json", cwd=tmp_path)
    assert p.returncode == 2 and "twice the contact distance" in p.stderr, p.stderr
    assert not (tmp_path / "out.json").exists()
