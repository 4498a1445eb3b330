"""Kinematic spheres on the command line (--kinematic-types): a bed of rough, inelastic spheres
settling on a frozen base of touching spheres (a lattice: kinematic spheres may overlap) stays
above it, the JSON keys and the energy budget with the work of a moving base; each refusal."""
import math

import pytest
from hs_run import run, run_json, refused

from tests.frozen_bed import BOX, write_bed



RUN = ["--boundary", "p,p,w", "--gravity", "0,0,-1", "--dt", 0.005, "--restitution", 0.6,
       "--tangential-restitution", 0.4, "--friction", 0.5]


def test_bed_on_a_frozen_base(hs, tmp_path):
    data = str(write_bed(tmp_path / "bed.data"))
    j = run_json(hs, "--read-data", data, "--kinematic-types", 2, *RUN, "--steps", 2000,
                 "--write-data", tmp_path / "end.data")
    assert j["kinematic_spheres"] == 36
    assert j["kinematic_collisions"] > 30
    assert j["kinematic_work"] == 0.0  # a frozen base does no work
    # Every contact's loss is in the totals: they close the budget.
    assert j["dissipated_energy_normal"] + j["dissipated_energy_tangential"] == pytest.approx(
        j["dissipated_energy"], rel=1e-9)
    # The base has not moved and no free sphere is in it (measured deepest: 1.8e-6 < g dt^2).
    rows = {}
    lines = (tmp_path / "end.data").read_text().split("Velocities")[0].splitlines()
    for line in lines:
        w = line.split()
        if len(w) >= 7 and w[0].isdigit() and w[1] in ("1", "2"):
            rows[int(w[0])] = (int(w[1]), float(w[2]) / 2, tuple(map(float, w[4:7])))
    base = [r for r in rows.values() if r[0] == 2]
    free = [r for r in rows.values() if r[0] == 1]
    assert sorted(p[2] for _, _, p in base) == [0.5] * 36
    for _, a, p in free:
        for _, b, q in base:
            d = [p[k] - q[k] for k in range(3)]
            for k in range(2):
                d[k] -= BOX[k] * round(d[k] / BOX[k])
            assert math.dist(d, (0, 0, 0)) > a + b - 2.5e-5


def test_moving_base_does_work_and_the_budget_closes(hs, tmp_path):
    data = str(write_bed(tmp_path / "bed.data", base_velocity=(0.2, 0.0, 0.0)))
    j = run_json(hs, "--read-data", data, "--kinematic-types", 2, *RUN, "--steps", 1000)
    assert j["kinematic_work"] > 0
    # Energy lost = what the contacts took - the work the moving base did.
    assert j["dissipated_energy_normal"] + j["dissipated_energy_tangential"] - j["kinematic_work"] == pytest.approx(
        j["dissipated_energy"], rel=1e-9, abs=1e-12)


def test_without_kinematic_types_the_touching_base_still_runs_as_free_spheres(hs, tmp_path):
    j = run_json(hs, "--read-data", str(write_bed(tmp_path / "bed.data")), *RUN, "--steps", 1)
    assert "kinematic_spheres" not in j  # no key where there are none


@pytest.mark.parametrize("args,needles", [
    (["--kinematic-types", "3"], ["--kinematic-types 3: no atom of type 3 in"]),
    (["--kinematic-types", "0"], ["--kinematic-types 0 must be >= 1"]),
    (["--kinematic-types", "2,x"], ["--kinematic-types 'x' is not a whole number"]),
    (["--kinematic-types", "2,2"], ["--kinematic-types: type 2 is given twice"]),
])
def test_bad_kinematic_types_are_refused(hs, tmp_path, args, needles):
    refused(run(hs, "--read-data", str(write_bed(tmp_path / "bed.data")), *RUN, "--steps", 1, *args), *needles)


def test_the_event_engine_refuses_kinematic_spheres(hs, tmp_path):
    refused(run(hs, "--read-data", str(write_bed(tmp_path / "bed.data")), "--boundary", "p,p,w", "--engine", "event",
                "--time", 1, "--kinematic-types", 2), "kinematic spheres (36)", "run them with the stepper")


def test_kinematic_types_need_a_data_file(hs):
    refused(run(hs, "--n", 100, "--steps", 1, "--kinematic-types", 1), "--kinematic-types requires --read-data")


def test_a_free_sphere_overlapping_a_kinematic_one_is_refused(hs, tmp_path):
    data = str(write_bed(tmp_path / "bed.data", free_overlap=True))
    refused(run(hs, "--read-data", data, "--kinematic-types", 2, *RUN, "--steps", 1), "overlaps atom")


def test_a_kinematic_sphere_running_into_a_wall_is_refused(hs, tmp_path):
    data = str(write_bed(tmp_path / "bed.data", base_velocity=(0.0, 0.0, 1.0)))
    refused(run(hs, "--read-data", data, "--kinematic-types", 2, *RUN, "--steps", 3000),
            "kinematic atom 1 moving at 1 along z reaches the wall")


def test_moving_kinematic_spheres_with_shaped_walls_are_refused(hs, tmp_path):
    """Only the box faces check a moving kinematic sphere's path: with a shaped wall it is refused."""
    data = str(write_bed(tmp_path / "bed.data", base_velocity=(0.1, 0.0, 0.0)))
    refused(run(hs, "--read-data", data, "--kinematic-types", 2, *RUN, "--steps", 1, "--wall", "plane 0 0 11 0 0 -1"),
            "atom 1 is kinematic and moving, with shaped walls")
