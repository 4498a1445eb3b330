"""Inputs at the edges of the arithmetic, through the command line: each is simulated correctly
or refused (exit 2, `hardsphere: error:` naming the value), and a run that ends with spheres
overlapping says so."""
import json
import math

import pytest
from hs_run import run, run_json, refused

from compare import lammps_files


def write_data(path, atoms, box=((0, 20),) * 3):
    """atoms: (x, y, z, vx, vy, vz[, diameter]) rows; ids from 1."""
    return lammps_files.write_data(path, lammps_files.spheres_from_rows(atoms, box=box, title="limits test"))


def gas_file(hs, path, *args):
    p = run(hs, "--steps", 0, "--write-data", path, *args)
    assert p.returncode == 0, p.stderr
    return path


# --- arithmetic overflow: refused, naming the value ----------------------------------------

def test_box_whose_length_overflows_is_refused(hs, tmp_path):
    f = write_data(tmp_path / "b.data", [(0, 0, 0, 1, 0, 0)], box=((-1e308, 1e308), (0, 20), (0, 20)))
    refused(run(hs, "--read-data", f, "--steps", 1), "1e+308")


def test_coordinate_that_cannot_be_wrapped_exactly_is_refused(hs, tmp_path):
    f = write_data(tmp_path / "c.data", [(1e17, 5, 5, 0, 0, 0), (5, 5, 5, 0, 0, 0)])
    refused(run(hs, "--read-data", f, "--steps", 1), "atom 1", "x = 1e+17", "cannot be resolved")


def test_box_far_beyond_double_resolution_is_refused(hs, tmp_path):
    f = write_data(tmp_path / "f.data", [(1e12 + 5, 1e12 + 5, 1e12 + 5, 0, 0, 0)],
                   box=((1e12, 1e12 + 20),) * 3)
    refused(run(hs, "--read-data", f, "--steps", 1), "box bound x = 1e+12", "origin")


@pytest.mark.parametrize("args,needle", [
    (["--dt", "1e300"], "dt = 1e+300"),
    (["--mass", "1e-300"], "mass 1e-300"),
    (["--temperature", "1e308"], "temperature"),
    (["--dt", "1e-10", "--precision", "float"], "dt = 1e-10"),
])
def test_options_that_overflow_are_refused(hs, tmp_path, args, needle):
    p = run(hs, "--n", 100, "--phi", 0.2, "--steps", 10, *args, "--json", "out.json", cwd=tmp_path)
    refused(p, needle)
    assert list(tmp_path.iterdir()) == []


def test_speed_whose_square_overflows_is_refused(hs, tmp_path):
    f = write_data(tmp_path / "v.data", [(5, 5, 5, 1e200, 0, 0), (10, 10, 10, 0, 0, 0)])
    refused(run(hs, "--read-data", f, "--steps", 1), "atom 1", "speed 1e+200")


@pytest.mark.parametrize("engine", [["--engine", "event", "--time", "1e300"], ["--dt", "0.01", "--steps", "100000000000000"]])
def test_runs_that_would_not_end_are_refused(hs, engine):
    refused(run(hs, "--n", 100, "--phi", 0.2, *engine), "more than the limit")


def test_event_engine_refuses_a_sphere_too_fast_to_follow(hs, tmp_path):
    f = write_data(tmp_path / "e.data", [(5, 5, 5, 1e90, 0, 0), (10, 10, 10, 0, 0, 0)])
    refused(run(hs, "--read-data", f, "--engine", "event", "--time", 1), "events")


# --- far from the origin, long steps: simulated correctly ----------------------------------

def test_float_run_far_from_the_origin_matches_the_run_at_the_origin(hs, tmp_path):
    # Over 10 seeds far / near collisions - 1 had mean 0.08% and sd 0.80% (|mean| + 4 sd = 3.3%).
    base = gas_file(hs, tmp_path / "g.data", "--n", 200, "--box", 8.06)
    far = lammps_files.read_data(base)
    far.box += 1e6
    far.pos += 1e6
    far = lammps_files.write_data(tmp_path / "far.data", far)
    near = run_json(hs, "--read-data", base, "--steps", 2000, "--precision", "float")
    moved = run_json(hs, "--read-data", far, "--steps", 2000, "--precision", "float")
    assert moved["collisions"] == pytest.approx(near["collisions"], rel=0.05)
    assert moved["max_overlap"] == 0 and moved["warnings"] == []
    assert moved["box"]["lo"] == [1e6] * 3


def test_long_steps_keep_the_event_engines_collision_rate(hs, tmp_path):
    # Over 10 seeds the rate ratio - 1 had mean 0.03% and sd 0.60% (dt 2), -0.01% and 0.31% (dt 5):
    # |mean| + 4 sd <= 2.4%.
    f = gas_file(hs, tmp_path / "g.data", "--n", 200, "--box", 8.06, "--seed", 2)
    ref = run_json(hs, "--read-data", f, "--engine", "event", "--time", 100)
    for dt in (2, 5):
        j = run_json(hs, "--read-data", f, "--dt", dt, "--time", 100)
        assert j["collision_rate_per_particle"] == pytest.approx(ref["collision_rate_per_particle"], rel=0.03), dt
        assert j["substeps"] > j["steps"] and j["max_overlap"] == 0 and j["warnings"] == []


# --- a run that ends overlapping warns ------------------------------------------------------

def test_overlap_left_by_a_missed_graze_is_reported(hs, tmp_path):
    # A (speed 2) grazes B within the step (overlap detection cannot see it) and stops at
    # t = 0.5, head-on against C, while inside B: the run ends with A and B overlapping by 0.1.
    atoms = [(5, 5, 5, 2, 0, 0), (6, 5.9, 5, 0, 0, 0), (7, 5, 5, 0, 0, 0)]
    f = write_data(tmp_path / "g.data", atoms)
    p = run(hs, "--read-data", f, "--dt", 1, "--steps", 1, "--detect", "overlap", "--json", "s.json", cwd=tmp_path)
    assert p.returncode == 0, p.stderr
    j = json.loads((tmp_path / "s.json").read_text())
    assert j["max_overlap"] == pytest.approx(0.1, abs=1e-9)
    assert any("overlap by up to" in w for w in j["warnings"])
    assert "hardsphere: warning: spheres overlap by up to 0.1" in p.stderr
    assert "--detect sweep" in p.stderr
    # Sweep detection sees the graze: no overlap, no warning.
    clean = run_json(hs, "--read-data", f, "--dt", 1, "--steps", 1, "--detect", "sweep")
    assert clean["max_overlap"] == 0 and clean["warnings"] == [] and clean["collisions"] >= 2


def test_walls_that_leave_no_room_are_refused(hs, tmp_path):
    # Exactly one diameter apart: a sphere moving across them would bounce infinitely often.
    tight = write_data(tmp_path / "t.data", [(5, 5, 0.5, 0, 0, 1)], box=((0, 10), (0, 10), (0, 1)))
    refused(run(hs, "--read-data", tight, "--boundary", "p,p,w", "--steps", 1), "walls along z", "1 apart")
    # 1e-12 wider: 1e10 bounces per step of 0.01, more than the stepper's per-step limit.
    gap = write_data(tmp_path / "g.data", [(5, 5, 0.5, 0, 0, 1)], box=((0, 10), (0, 10), (0, 1 + 1e-12)))
    refused(run(hs, "--read-data", gap, "--boundary", "p,p,w", "--steps", 10), "bounce")
    # One rounding wider: 4.5e15 bounces per unit time, more than the event engine's work limit.
    gap = write_data(tmp_path / "h.data", [(5, 5, 0.5, 0, 0, 1)], box=((0, 10), (0, 10), (0, math.nextafter(1, 2))))
    refused(run(hs, "--read-data", gap, "--boundary", "p,p,w", "--engine", "event", "--time", 1), "wall bounces")


# --- big spheres ------------------------------------------------------------------------------

def test_periodic_box_too_short_for_a_big_sphere_is_refused(hs, tmp_path):
    # Diameter 15 in a periodic box of 20: one cell is narrower than the sphere, and the pass
    # for big spheres would reach past half the box.
    small = [(1, 1, z, 0.1, 0, 0, 1.0) for z in (1, 3, 5, 15, 17)]
    f = write_data(tmp_path / "big.data", [(10, 10, 10, 0, 0, 0, 15.0)] + small)
    refused(run(hs, "--read-data", f, "--steps", 1), "box length 20", "diameter 15")


def test_big_sphere_in_a_fine_user_grid_runs(hs, tmp_path):
    # Cells 2 wide around a sphere 6 across: the big sphere's own pass lists its pairs.
    small = [(x, 2, 2, 0.3, 0.1, 0, 1.0) for x in range(1, 20, 2)]
    f = write_data(tmp_path / "fine.data", [(10, 10, 10, -0.2, 0, 0, 6.0)] + small)
    j = run_json(hs, "--read-data", f, "--steps", 100, "--cells", 10)
    assert j["cells_per_dim"] == [10, 10, 10]
    assert j["max_overlap"] == 0


# --- angular velocities (issue 42, items 3, 7, 15) ------------------------------------------

def spin_file(path, w1, w2=(0.125, 7, -1.5)):
    """Two spheres 3 apart meeting at t = 1, with the given angular velocities (Velocities line 17
    for atom 1)."""
    data = lammps_files.spheres([(2, 5, 5), (5, 5, 5)], [(1, 0, 0), (-1, 0, 0)], box=((0, 10),) * 3,
                                density=lammps_files.UNIT_DENSITY, omega=[w1, w2], title="spins")
    lammps_files.write_data(path, data)
    return path


@pytest.mark.parametrize("engine", [["--steps", 300], ["--steps", 300, "--precision", "float"],
                                    ["--engine", "event", "--time", 3]])
def test_smooth_spheres_keep_their_spins(hs, tmp_path, engine):
    f = spin_file(tmp_path / "s.data", (0.5, -0.25, 3), (-0.0, 1e-310, 1e100))
    j = run_json(hs, "--read-data", f, *engine, "--write-data", tmp_path / "out.data", "--dump", tmp_path / "d.dump")
    assert j["collisions"] == 1
    before, after = lammps_files.read_data(f), lammps_files.read_data(tmp_path / "out.data")
    assert after.omega.tobytes() == before.omega.tobytes()  # bit for bit, -0 and subnormals too
    frames = lammps_files.read_dump_frames(tmp_path / "d.dump")
    assert frames[-1]["wz"].tolist() == [3.0, 1e100]


@pytest.mark.parametrize("args,needles", [
    # float, rough: a surface speed float cannot carry
    (["--precision", "float", "--tangential-restitution", 1, "--steps", 100],
     ["stepper in single precision: ", "s.data:17: atom 1: angular velocity 0 0 1e+45", "above 6.98146e+09"]),
    # double: the square of the surface speed would overflow, whatever the law
    (["--steps", 100, "W200"], ["s.data:17: atom 1: angular velocity 1e+200 0 1e+200", "would overflow"]),
    (["--engine", "event", "--time", 1, "W200"], ["s.data:17: atom 1: angular velocity 1e+200 0 1e+200"]),
    # a spin whose speed no step or clock follows: refused up front, not as a jam or an endless step
    (["--tangential-restitution", 1, "--steps", 1000, "W20"],
     ["particle-steps", "the rotation of ", "s.data:17: atom 1 (angular velocity 0 0 1e+20) into a speed of 3.16228e+19"]),
    (["--tangential-restitution", 1, "--engine", "event", "--time", 3, "W20"],
     ["events", "s.data:17: atom 1 (angular velocity 0 0 1e+20) alone up to 3.16228e+19"]),
])
def test_angular_velocities_beyond_the_arithmetic_are_refused(hs, tmp_path, args, needles):
    w1 = (1e200, 0, 1e200) if "W200" in args else (0, 0, 1e20) if "W20" in args else (0, 0, 1e45)
    f = spin_file(tmp_path / "s.data", w1, (0, 0, -w1[2]) if "W200" not in args else (0, -1e200, 0))
    p = run(hs, "--read-data", f, *[a for a in args if a not in ("W200", "W20")], "--json", tmp_path / "j.json")
    refused(p, *needles)
    assert "jammed" not in p.stderr and not (tmp_path / "j.json").exists()
