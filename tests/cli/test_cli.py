"""The `hardsphere run` command as users meet it: JSON contract, files, and every bad input.

Bad input must end with exit status 2, a message naming the offending value (and the data
file line where there is one), and no output file left behind, not even a partial one.
"""
import json
import math
from pathlib import Path

import numpy as np
import pytest
from hs_run import run, run_json

from compare.lammps_files import read_data

JSON_KEYS = [
    "n", "packing_fraction", "box", "steps", "dt", "sim_time", "cells_per_dim", "loop_cpu_seconds",
    "particle_steps_per_second", "collisions", "kinetic_energy_initial", "kinetic_energy_final",
    "energy_rel_drift", "momentum_initial", "momentum_final", "temperature", "compressibility_factor",
    "max_overlap", "wall_collisions", "speed_histogram", "speed_ks_distance", "seed", "scene_kernel", "detect",
    "restitution", "contact_time", "dissipated_energy",
]


def write_state(hs, path, *args):
    p = run(hs, "--n", 50, "--phi", 0.1, "--steps", 0, "--write-data", path, *args)
    assert p.returncode == 0, p.stderr
    return Path(path).read_text()


def same_state(a, b):
    """Two data files hold the same box and atoms, every number equal."""
    fields = ("box", "ids", "types", "diameter", "density", "pos", "image", "vel", "omega")
    return all(np.array_equal(getattr(a, f), getattr(b, f)) for f in fields)


# --- the contract ---------------------------------------------------------------------------

def test_json_summary_has_every_documented_key(hs):
    j = run_json(hs, "--n", 500, "--phi", 0.3, "--steps", 50, "--dt", 0.01)
    for key in JSON_KEYS:
        assert key in j, key
    assert j["n"] == 500 and j["steps"] == 50
    assert j["sim_time"] == pytest.approx(0.5)
    assert j["packing_fraction"] == pytest.approx(0.3, rel=1e-12)
    assert j["collisions"] > 0
    assert abs(j["energy_rel_drift"]) < 1e-12
    assert j["max_overlap"] == 0
    assert sum(j["speed_histogram"]["counts"]) == 500


def test_same_seed_same_result_other_seed_other_result(hs, tmp_path):
    a = run_json(hs, "--n", 300, "--phi", 0.3, "--steps", 100, "--seed", 5, "--write-data", tmp_path / "a.data")
    b = run_json(hs, "--n", 300, "--phi", 0.3, "--steps", 100, "--seed", 5, "--write-data", tmp_path / "b.data")
    c = run_json(hs, "--n", 300, "--phi", 0.3, "--steps", 100, "--seed", 6)
    assert a["collisions"] == b["collisions"] != c["collisions"]
    assert (tmp_path / "a.data").read_text() == (tmp_path / "b.data").read_text()


def test_data_file_round_trip_is_bit_exact(hs, tmp_path):
    write_state(hs, tmp_path / "first.data", "--boundary", "p,p,w")
    p = run(hs, "--read-data", tmp_path / "first.data", "--boundary", "p,p,w", "--steps", 0,
            "--write-data", tmp_path / "second.data")
    assert p.returncode == 0, p.stderr
    assert same_state(read_data(tmp_path / "first.data"), read_data(tmp_path / "second.data"))  # %.17g round-trips


def test_run_continues_from_its_own_data_file(hs, tmp_path):
    # 100 steps at once, or 50 + 50 through a data file: same collisions (state is exact).
    write_state(hs, tmp_path / "s.data")
    whole = run_json(hs, "--read-data", tmp_path / "s.data", "--steps", 100)
    half = run_json(hs, "--read-data", tmp_path / "s.data", "--steps", 50, "--write-data", tmp_path / "h.data")
    rest = run_json(hs, "--read-data", tmp_path / "h.data", "--steps", 50)
    assert half["collisions"] + rest["collisions"] == whole["collisions"]


def test_dump_has_one_frame_per_interval(hs, tmp_path):
    dump = tmp_path / "t.dump"
    run_json(hs, "--n", 40, "--phi", 0.1, "--steps", 30, "--dump", dump, "--dump-every", 10)
    text = dump.read_text()
    assert text.count("ITEM: TIMESTEP") == 4  # steps 0, 10, 20, 30
    assert "ITEM: ATOMS id type radius x y z vx vy vz" in text


def test_walls_one_box_and_sweep_mode_run(hs):
    j = run_json(hs, "--n", 200, "--phi", 0.2, "--boundary", "w", "--cells", 1, "--detect", "sweep", "--steps", 50)
    assert j["cells_per_dim"] == [1, 1, 1]
    assert j["wall_collisions"] > 0
    assert j["box"]["boundary"] == "w,w,w"


def test_auto_detection_sweeps_long_steps_only(hs):
    # One speed 1 (v_rms = 1), unit diameters: auto switches to sweep above dt = 0.1.
    for dt, mode in [(0.05, "overlap"), (0.2, "sweep")]:
        j = run_json(hs, "--n", 300, "--phi", 0.2, "--init-speed", 1.0, "--dt", dt, "--steps", 5)
        assert j["detect"] == mode and j["scene_kernel"].endswith("," + mode)
    j = run_json(hs, "--n", 300, "--phi", 0.2, "--dt", 0.2, "--steps", 5, "--detect", "overlap")
    assert j["detect"] == "overlap"


def test_init_speed_gives_every_sphere_one_speed(hs, tmp_path):
    write_state(hs, tmp_path / "s.data", "--init-speed", 2.0)
    v = read_data(tmp_path / "s.data").vel
    speeds = np.sqrt((v ** 2).sum(axis=1))
    assert max(speeds) == pytest.approx(2.0, rel=1e-12) and min(speeds) == pytest.approx(2.0, rel=1e-12)
    assert v[:, 0].sum() == pytest.approx(0.0, abs=1e-12)


# --- bad input ------------------------------------------------------------------------------

OUTPUTS = ("out.json", "out.data", "out.dump")


def assert_rejected(hs, tmp_path, args, *needles, status=2):
    p = run(hs, *args, "--json", "out.json", "--write-data", "out.data", "--dump", "out.dump", cwd=tmp_path)
    assert p.returncode == status, (p.returncode, p.stdout, p.stderr)
    for needle in needles:
        assert needle in p.stderr, (needle, p.stderr)
    left = sorted(str(f.name) for f in tmp_path.iterdir() if f.name.startswith("out"))
    assert left == [], f"partial outputs left behind: {left}"


@pytest.mark.parametrize("args,needles", [
    (["--radius", "-1"], ["--radius", "-1"]),
    (["--mass", "0"], ["mass", "0"]),
    (["--box", "0"], ["box", "0"]),
    (["--box", "10,nan,10"], ["nan"]),
    (["--phi", "inf"], ["--phi", "inf"]),
    (["--dt", "0"], ["dt = 0"]),
    (["--dt", "-0.5"], ["dt = -0.5"]),
    (["--n", "0"], ["--n 0"]),
    (["--temperature", "-1"], ["temperature -1"]),
    (["--n", "1000", "--phi", "0.7"], ["0.7", "0.64"]),
    (["--n", "1000", "--phi", "0.6", "--init", "lattice"], ["0.6", "0.55", "--init dense"]),
    (["--n", "1000", "--phi", "0.35", "--init", "random"], ["0.35", "--init lattice"]),
    (["--cells", "0"], ["--cells '0'"]),
    (["--cells", "80"], ["cells 80,80,80"]),
    (["--boundary", "p,x,p"], ["x"]),
    (["--precision", "quad"], ["quad"]),
    (["--detect", "psychic"], ["psychic"]),
    (["--init", "crystal"], ["crystal"]),
    (["--seed", "-1"], ["--seed '-1'"]),
    (["--seed", "18446744073709551616"], ["--seed '18446744073709551616'"]),
    (["--seed", "7x"], ["--seed '7x'"]),
    (["--histogram-bins", "-3"], ["--histogram-bins -3"]),
])
def test_bad_option_values(hs, tmp_path, args, needles):
    assert_rejected(hs, tmp_path, ["--steps", "5", *args], *needles)


def test_unknown_option_is_refused(hs, tmp_path):
    p = run(hs, "--frobnicate", "3", cwd=tmp_path)
    assert p.returncode != 0 and "--frobnicate" in (p.stderr + p.stdout)


def test_conflicting_options_are_refused(hs, tmp_path):
    write_state(hs, tmp_path / "s.data")
    p = run(hs, "--read-data", tmp_path / "s.data", "--n", 10)
    assert p.returncode != 0 and "--n" in (p.stderr + p.stdout)
    p = run(hs, "--n", 10, "--phi", 0.1, "--box", 10)
    assert p.returncode == 2 and "--phi and --box" in p.stderr


def edited(text, section, row, column, value):
    """Replaces one number (0-based row and column) in a data-file section."""
    lines = text.splitlines()
    start = next(i for i, l in enumerate(lines) if l.split("#")[0].strip() == section) + 2
    parts = lines[start + row].split()
    parts[column] = value
    lines[start + row] = " ".join(parts)
    return "\n".join(lines) + "\n", start + row + 1  # the 1-based file line


@pytest.mark.parametrize("section,column,value,needles", [
    ("Atoms", 2, "-1", ["diameter", "-1"]),
    ("Atoms", 2, "0", ["diameter", "0"]),
    ("Atoms", 3, "0", ["density", "0"]),
    ("Atoms", 4, "nan", ["nan"]),
    ("Atoms", 6, "1.2.3", ["1.2.3"]),
    ("Velocities", 2, "inf", ["inf"]),
    ("Velocities", 1, "abc", ["abc"]),
])
def test_malformed_values_in_data_files_name_value_and_line(hs, tmp_path, section, column, value, needles):
    text, line = edited(write_state(hs, tmp_path / "s.data"), section, 3, column, value)
    bad = tmp_path / "bad.data"
    bad.write_text(text)
    assert_rejected(hs, tmp_path, ["--read-data", bad], *needles)
    p = run(hs, "--read-data", bad)
    if value not in ("-1", "0", "nan", "inf"):  # parse errors carry the line; range errors the atom id
        assert f"bad.data:{line}" in p.stderr, p.stderr


def test_overlapping_particles_in_data_file(hs, tmp_path):
    text = write_state(hs, tmp_path / "s.data")
    d = read_data(tmp_path / "s.data")  # rows in id order, as hardsphere writes them
    x, y, z = d.pos[0]
    text, _ = edited(text, "Atoms", 1, 4, repr(x + 0.3))
    text, _ = edited(text, "Atoms", 1, 5, repr(y))
    text, _ = edited(text, "Atoms", 1, 6, repr(z))
    (tmp_path / "bad.data").write_text(text)
    assert_rejected(hs, tmp_path, ["--read-data", "bad.data"], "overlap", f"{d.ids[0]}", f"{d.ids[1]}")


def test_particle_outside_a_wall_box(hs, tmp_path):
    text, _ = edited(write_state(hs, tmp_path / "s.data", "--boundary", "w"), "Atoms", 2, 6, "-3")
    (tmp_path / "bad.data").write_text(text)
    assert_rejected(hs, tmp_path, ["--read-data", "bad.data", "--boundary", "w"], "z = -3", "outside")


def test_truncated_and_structurally_broken_data_files(hs, tmp_path):
    text = write_state(hs, tmp_path / "s.data")
    lines = text.splitlines()
    cut = next(i for i, l in enumerate(lines) if l.startswith("Velocities"))
    (tmp_path / "truncated.data").write_text("\n".join(lines[: cut - 5]) + "\n")
    assert_rejected(hs, tmp_path, ["--read-data", "truncated.data"], "truncated.data")
    (tmp_path / "noatoms.data").write_text("\n".join(lines[:10]) + "\n")
    assert_rejected(hs, tmp_path, ["--read-data", "noatoms.data"], "noatoms.data", "Atoms")
    (tmp_path / "style.data").write_text(text.replace("Atoms # sphere", "Atoms # atomic"))
    assert_rejected(hs, tmp_path, ["--read-data", "style.data"], "atomic")
    dup = text.replace("\n2 1 ", "\n1 1 ", 1)
    (tmp_path / "dup.data").write_text(dup)
    assert_rejected(hs, tmp_path, ["--read-data", "dup.data"], "dup.data:", "atom id 1 appears twice")
    assert_rejected(hs, tmp_path, ["--read-data", "missing.data"], "missing.data")


@pytest.mark.parametrize("engine", [("--steps", 500, "--dt", 0.02), ("--engine", "event", "--time", 10)])
def test_restitution_cools_the_gas_and_accounts_the_energy(hs, engine):
    # Dilute gas, e = 0.8: Haff's law with the Enskog rate (Carnahan-Starling contact value)
    # T(10) = 1 / (1 + (1 - e^2) G0 10 / 6)^2 = 0.506 at phi 0.05; the energy the collisions
    # took is E0 - E1 and the total momentum stays zero. Over 10 seeds T / T_Haff - 1 had mean
    # +0.71% and sd 0.65% (stepper), +0.60% and 0.74% (event): |mean| + 4 sd <= 3.6%.
    j = run_json(hs, "--n", 2000, "--phi", 0.05, "--restitution", 0.8, *engine)
    phi, e = 0.05, 0.8
    g = (1 - phi / 2) / (1 - phi) ** 3
    g0 = 4 * (6 * phi / math.pi) * g * math.sqrt(math.pi)
    assert j["temperature"] == pytest.approx(1 / (1 + (1 - e * e) * g0 * 10 / 6) ** 2, rel=0.04)
    assert j["restitution"] == 0.8 and j["contact_time"] == 1e-4
    assert j["dissipated_energy"] == pytest.approx(j["kinetic_energy_initial"] - j["kinetic_energy_final"])
    assert j["dissipated_energy"] > 0.4 * j["kinetic_energy_initial"]
    assert max(abs(p) for p in j["momentum_final"]) < 1e-9


@pytest.mark.parametrize("args, message", [
    (("--restitution", 0), "--restitution 0 must be in (0, 1]"),
    (("--restitution", 1.2), "--restitution 1.2 must be in (0, 1]"),
    (("--restitution", "nan"), "--restitution"),
    (("--restitution", 0.5, "--contact-time", -1), "--contact-time -1 must be finite and >= 0"),
    (("--contact-time", 0.1), "--contact-time 0.1 has no effect with --restitution 1"),
    (("--restitution", 1, "--contact-time", 0.1), "--contact-time 0.1 has no effect with --restitution 1"),
    (("--resting-time", 0.3), "--resting-time 0.3 has no effect without gravity"),
    (("--boundary", "p,p,w", "--gravity", "0,0,0", "--resting-time", 0.3), "--resting-time 0.3 has no effect"),
])
def test_bad_restitution_is_refused(hs, args, message):
    p = run(hs, "--n", 100, "--steps", 1, *args)
    assert p.returncode == 2 and message in p.stderr and p.stderr.startswith("hardsphere: error:"), p.stderr


@pytest.mark.parametrize("engine", [("--steps", 1000), ("--engine", "event", "--time", 10)])
def test_gravity_keeps_kinetic_plus_potential_energy(hs, engine):
    j = run_json(hs, "--n", 300, "--box", "10,10,30", "--boundary", "p,p,w", "--gravity", "0,0,-1", *engine)
    assert j["gravity"] == [0, 0, -1]
    assert j["kinetic_energy_final"] > 2 * j["kinetic_energy_initial"]  # the spheres fell
    assert j["potential_energy_final"] < j["potential_energy_initial"]
    assert abs(j["energy_rel_drift"]) < 1e-12 and abs(j["dissipated_energy"]) < 1e-9 * j["potential_energy_initial"]


@pytest.mark.parametrize("engine", [("--steps", 500), ("--engine", "event", "--time", 10)])
def test_gravity_along_a_periodic_axis_runs_and_warns(hs, engine):
    # A chute without wall friction (smooth walls take no momentum along x): it runs, warns on
    # stderr before the run why it cannot settle, and its energy budget takes the unwrapped
    # heights along x, so it closes to rounding although the spheres cross the box several times.
    p = run(hs, "--n", 100, "--box", "10,10,10", "--boundary", "p,p,w", "--gravity", "0.5,0,-1", "--json", "-",
            *engine)
    assert p.returncode == 0, p.stderr
    assert p.stderr.startswith("hardsphere: warning: --gravity along periodic axis x (0.5) with no frictional wall")
    assert "--wall-tangential-restitution" in p.stderr
    j = json.loads(p.stdout)
    assert j["gravity"] == [0.5, 0, -1]
    assert j["potential_energy_final"] < j["potential_energy_initial"] - 100 * 2  # fell more than 2 units in x
    assert abs(j["energy_rel_drift"]) < 1e-12 and abs(j["dissipated_energy"]) < 1e-9 * abs(j["potential_energy_initial"])
    # Gravity along wall axes only: no warning.
    q = run(hs, "--n", 100, "--box", "10,10,10", "--boundary", "p,p,w", "--gravity", "0,0,-1", *engine)
    assert q.returncode == 0 and "warning" not in q.stderr, q.stderr


@pytest.mark.parametrize("args, message", [
    (("--gravity", "-1", "--boundary", "w"), "--gravity '-1' needs three values gx,gy,gz"),
    (("--gravity", "0,0,x", "--boundary", "w"), "is not a number"),
    # A gravity whose bounces no run could finish is refused up front, in both engines.
    (("--gravity", "0,0,-1e300", "--boundary", "p,p,w", "--steps", 10), "the run would take"),
    (("--gravity", "0,0,-1e300", "--boundary", "p,p,w", "--engine", "event", "--time", 1), "the run would take at least"),
])
def test_bad_gravity_is_refused(hs, args, message):
    p = run(hs, "--n", 100, *args)
    assert p.returncode == 2 and message in p.stderr and p.stderr.startswith("hardsphere: error:"), p.stderr
