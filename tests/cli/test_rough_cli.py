"""Rough spheres on the command line: options accepted and refused, angular velocities through
data files and dumps, and the JSON keys of rough scenes (absent from smooth ones)."""
import math

import numpy as np
import pytest
from hs_run import run, run_json, refused

from compare.lammps_files import read_data

ROUGH_KEYS = [
    "tangential_restitution", "friction", "inertia",
    "temperature_translational_initial", "temperature_translational_final",
    "temperature_rotational_initial", "temperature_rotational_final",
    "kinetic_energy_translational_initial", "kinetic_energy_translational_final",
    "kinetic_energy_rotational_initial", "kinetic_energy_rotational_final",
    "dissipated_energy_normal", "dissipated_energy_tangential",
]
SMALL = ["--n", 300, "--phi", 0.2]


@pytest.mark.parametrize("args,needles", [
    (["--tangential-restitution", 1.5], ["--tangential-restitution 1.5", "[-1, 1]"]),
    (["--tangential-restitution", -1.01], ["--tangential-restitution -1.01"]),
    (["--tangential-restitution", "x"], ["--tangential-restitution 'x'"]),
    (["--tangential-restitution", 0.5, "--friction", -0.1], ["--friction -0.1", ">= 0"]),
    (["--friction", 0.5], ["--friction", "--tangential-restitution"]),
    (["--tangential-restitution", -1, "--friction", 0.5], ["--friction 0.5", "beta0"]),
    (["--tangential-restitution", 0.5, "--inertia", 0.7], ["--inertia 0.7", "(0, 2/3]"]),
    (["--tangential-restitution", 0.5, "--inertia", 0], ["--inertia 0"]),
    (["--tangential-restitution", -1, "--inertia", 0.3], ["--inertia 0.3", "smooth"]),
    (["--inertia", 0.3], ["--inertia", "--tangential-restitution"]),
    (["--tangential-restitution", 0.5, "--rotational-temperature", -1], ["--rotational-temperature -1", ">= 0"]),
    (["--tangential-restitution", -1, "--rotational-temperature", 2], ["--rotational-temperature 2", "smooth"]),
])
def test_bad_rough_options_are_refused(hs, args, needles):
    refused(run(hs, *SMALL, "--steps", 1, *args), *needles)


def test_rotational_temperature_excludes_read_data(hs, tmp_path):
    p = run(hs, *SMALL, "--steps", 0, "--write-data", tmp_path / "s.data")
    assert p.returncode == 0, p.stderr
    refused(run(hs, "--read-data", tmp_path / "s.data", "--tangential-restitution", 0.5,
                "--rotational-temperature", 1), "--rotational-temperature")


@pytest.mark.parametrize("engine", [["--steps", 100], ["--engine", "event", "--time", 1]])
def test_rough_json_keys_and_energy_bookkeeping(hs, engine):
    smooth = run_json(hs, *SMALL, *engine)
    for key in ROUGH_KEYS:
        assert key not in smooth
    j = run_json(hs, *SMALL, *engine, "--tangential-restitution", 0.3, "--restitution", 0.9, "--friction", 0.4,
                 "--inertia", 0.5, "--rotational-temperature", 2)
    for key in ROUGH_KEYS:
        assert key in j, key
    assert j["tangential_restitution"] == 0.3 and j["friction"] == 0.4 and j["inertia"] == 0.5
    # T_rot = sum I w^2 / 3N at the start: drawn at 2, within 5 standard errors sqrt(2/(3N)) of it
    # (over 10 seeds its departure had mean 0.37 and sd 0.87 of them: |mean| + 4 sd = 3.9).
    assert abs(j["temperature_rotational_initial"] / 2 - 1) < 5 * math.sqrt(2 / (3 * 300))
    assert j["kinetic_energy_rotational_initial"] == pytest.approx(1.5 * 300 * j["temperature_rotational_initial"])
    # The energy lost is the sum of the channels, and dissipated_energy counts rotation too.
    lost = (j["kinetic_energy_translational_initial"] + j["kinetic_energy_rotational_initial"]
            - j["kinetic_energy_translational_final"] - j["kinetic_energy_rotational_final"])
    assert lost > 0
    assert j["dissipated_energy"] == pytest.approx(lost, rel=1e-9)
    assert j["dissipated_energy_normal"] + j["dissipated_energy_tangential"] == pytest.approx(lost, rel=1e-9)
    assert j["dissipated_energy_normal"] > 0 and j["dissipated_energy_tangential"] > 0
    # Constant beta: friction is reported as null (no Coulomb limit).
    k = run_json(hs, *SMALL, *engine, "--tangential-restitution", 1)
    assert k["friction"] is None
    assert abs(k["energy_rel_drift"]) < 1e-12
    # Default rotational temperature: the translational one (1).
    assert abs(k["temperature_rotational_initial"] - 1) < 5 * math.sqrt(2 / (3 * 300))


def test_rough_scene_starts_from_the_smooth_scenes_positions_and_velocities(hs, tmp_path):
    run_json(hs, *SMALL, "--steps", 0, "--write-data", tmp_path / "smooth.data")
    run_json(hs, *SMALL, "--steps", 0, "--write-data", tmp_path / "rough.data", "--tangential-restitution", 0.5)
    a, b = read_data(tmp_path / "smooth.data"), read_data(tmp_path / "rough.data")
    assert np.array_equal(a.pos, b.pos) and np.array_equal(a.vel, b.vel)
    assert not a.omega.any() and b.omega.any()


@pytest.mark.parametrize("engine", [["--steps", 60], ["--engine", "event", "--time", 0.6]])
def test_omegas_round_trip_through_data_files(hs, tmp_path, engine):
    rough = ["--tangential-restitution", 0.5, "--friction", 0.3]
    run_json(hs, *SMALL, "--steps", 0, "--write-data", tmp_path / "s.data", *rough)
    s = read_data(tmp_path / "s.data")
    assert s.omega is not None and s.omega.any()
    # Read back and written again with no step: the same numbers bit for bit.
    run_json(hs, "--read-data", tmp_path / "s.data", "--steps", 0, "--write-data", tmp_path / "t.data", *rough)
    t = read_data(tmp_path / "t.data")
    assert np.array_equal(s.omega, t.omega) and np.array_equal(s.vel, t.vel)
    # The run from the file: its summary starts from the file's rotational energy, and the omegas
    # it ends with are written and change the run that continues from them.
    j = run_json(hs, "--read-data", tmp_path / "s.data", *engine, "--write-data", tmp_path / "u.data", *rough)
    q = 0.4
    r = 0.5 * s.diameter
    m = s.density * 4 / 3 * np.pi * r**3
    assert j["kinetic_energy_rotational_initial"] == pytest.approx(0.5 * np.sum(q * m * r**2 * np.sum(s.omega**2, 1)))
    u = read_data(tmp_path / "u.data")
    assert j["kinetic_energy_rotational_final"] == pytest.approx(0.5 * np.sum(q * m * r**2 * np.sum(u.omega**2, 1)))
    # Zeroing the omegas of the file changes the run: they are used, not only carried.
    z = read_data(tmp_path / "s.data")
    text = (tmp_path / "s.data").read_text().split("Velocities")
    rows = text[1].strip().splitlines()
    text[1] = "\n\n" + "\n".join(" ".join(line.split()[:4] + ["0", "0", "0"]) for line in rows) + "\n"
    (tmp_path / "z.data").write_text("Velocities".join(text))
    assert not read_data(tmp_path / "z.data").omega.any() and z.omega.any()
    k = run_json(hs, "--read-data", tmp_path / "z.data", *engine, *rough)
    assert k["kinetic_energy_rotational_initial"] == 0
    assert k["dissipated_energy_tangential"] != j["dissipated_energy_tangential"]


def test_continuing_a_rough_run_through_a_data_file(hs, tmp_path):
    rough = ["--tangential-restitution", 0.5, "--restitution", 0.95]
    run_json(hs, *SMALL, "--steps", 0, "--write-data", tmp_path / "s.data", *rough)
    whole = run_json(hs, "--read-data", tmp_path / "s.data", "--steps", 100, *rough)
    half = run_json(hs, "--read-data", tmp_path / "s.data", "--steps", 50, "--write-data", tmp_path / "h.data", *rough)
    rest = run_json(hs, "--read-data", tmp_path / "h.data", "--steps", 50, *rough)
    assert half["collisions"] + rest["collisions"] == whole["collisions"]
    assert rest["kinetic_energy_rotational_final"] == pytest.approx(whole["kinetic_energy_rotational_final"],
                                                                    rel=1e-9)


@pytest.mark.parametrize("engine", [["--steps", 20], ["--engine", "event", "--time", 0.2]])
def test_dumps_carry_omegas_when_rough_only(hs, tmp_path, engine):
    rough = ["--tangential-restitution", 0.5]
    steps = [] if "event" in engine else ["--dump-every", 10]
    run_json(hs, *SMALL, *engine, "--dump", tmp_path / "r.dump", *steps, *rough,
             "--write-data", tmp_path / "r.data")
    run_json(hs, *SMALL, *engine, "--dump", tmp_path / "s.dump", *steps)
    rough_text, smooth_text = (tmp_path / "r.dump").read_text(), (tmp_path / "s.dump").read_text()
    assert "ITEM: ATOMS id type radius x y z vx vy vz ix iy iz wx wy wz\n" in rough_text
    assert "ITEM: ATOMS id type radius x y z vx vy vz ix iy iz\n" in smooth_text
    # The last frame's omegas are the final state's.
    last = rough_text.split("ITEM: ATOMS")[-1].strip().splitlines()[1:]
    table = np.array([[float(x) for x in line.split()] for line in last])
    table = table[np.argsort(table[:, 0])]
    final = read_data(tmp_path / "r.data")
    np.testing.assert_allclose(table[:, 12:15], final.omega[np.argsort(final.ids)], rtol=1e-5, atol=1e-12)
