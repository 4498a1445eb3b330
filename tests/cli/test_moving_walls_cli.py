"""Walls whose geometry moves (--wall ... translate / wiggle): the rebound off a moving plate, the
bouncing-ball threshold of a wiggled plate, the energy budget of a vibrated bed, a piston, the
refusals and the JSON's words."""
import math

import pytest
from hs_run import run, run_json, refused

BOX = ["--n", 40, "--box", 20, "--boundary", "w", "--steps", 5]
TWO_PI = 2 * math.pi


def one_sphere(tmp_path, z, vz=0.0, name="one.data", zlo=-5):
    data = tmp_path / name
    data.write_text(f"one\n\n1 atoms\n1 atom types\n0 20 xlo xhi\n0 20 ylo yhi\n{zlo} 40 zlo zhi\n\n"
                    f"Atoms # sphere\n\n1 1 1 1 10 10 {z}\n\nVelocities\n\n1 0 0 {vz}\n")
    return data


def track(path):
    return [[float(x) for x in line.split()] for line in open(path) if not line.startswith("#")]


def test_a_sphere_rebounds_off_a_plate_moving_up_with_u_minus_e_v_minus_u(hs, tmp_path):
    # v = -1 onto a plate moving up at u = 0.5, e = 0.5: v' = u - e (v - u) = 1.25, whatever the
    # contact time (no gravity); the wall's work is the energy change plus what restitution took.
    data = one_sphere(tmp_path, 5, -1)
    out = tmp_path / "out.data"
    j = run_json(hs, "--read-data", data, "--boundary", "p,p,w", "--steps", 400, "--dt", 0.01,
                 "--wall", "plane 0 0 1 0 0 1 translate 0 0 0.5 restitution 0.5", "--write-data", out)
    vz = float(out.read_text().split("Velocities")[1].split()[3])
    assert vz == pytest.approx(1.25, abs=1e-12)
    m = math.pi / 6
    gained = 0.5 * m * (1.25 ** 2 - 1)
    taken = 0.5 * m * (1.5 ** 2 - 0.75 ** 2)  # relative normal speeds before and after
    assert j["shaped_walls"][0]["wall"] == "plane 0 0 1 0 0 1 translate 0 0 0.5 restitution 0.5"
    assert j["shaped_walls"][0]["collisions"] == 1
    assert j["wall_work"] == pytest.approx(gained + taken, rel=1e-12)


@pytest.mark.parametrize("amplitude,rides", [(0.9, True), (1.1, False)])
def test_a_sphere_rides_a_wiggled_plate_below_g_and_leaves_it_above(hs, tmp_path, amplitude, rides):
    # A plate wiggled along z with period 2 pi (omega 1) under g = 1: peak acceleration A. At
    # A = 0.9 < g the sphere resting on it stays within resting hops of it (measured: gap <=
    # 1.5e-7 over 30 time units); at A = 1.1 it leaves when the plate's acceleration A cos t
    # first falls below -g, t = acos(-1/1.1) = 2.711 (measured: first gap > 1e-6 at t = 2.74,
    # the tracker's sample after it, dt 0.01).
    data = one_sphere(tmp_path, 0.5)
    tr = tmp_path / "track.txt"
    run_json(hs, "--read-data", data, "--boundary", "p,p,w", "--gravity", "0,0,-1", "--steps", 3000, "--dt", 0.01,
             "--wall", f"plane 0 0 0 0 0 1 wiggle z {amplitude} {TWO_PI!r}", "--track", 1, "--track-every", 0.01,
             "--track-file", tr)
    gaps = [(r[0], r[3] - 0.5 - amplitude * (1 - math.cos(r[0]))) for r in track(tr)]
    assert min(g for _, g in gaps) > -1e-9
    if rides:
        assert max(g for _, g in gaps) < 1e-6
    else:
        leave = next(t for t, g in gaps if g > 1e-6)
        assert math.acos(-1 / amplitude) <= leave <= math.acos(-1 / amplitude) + 0.05


def test_a_vibrated_bed_closes_its_energy_budget(hs):
    # An inelastic rough bed on a floor wiggled at 2 g: the wall's work is the energy change plus
    # what the contacts took, to rounding (the drum test's identity, with moving geometry).
    j = run_json(hs, "--n", 100, "--box", 10, "--boundary", "p,p,w", "--gravity", "0,0,-1", "--restitution", 0.8,
                 "--tangential-restitution", 0.3,
                 "--dt", 0.005, "--steps", 2000, "--wall", "plane 0 0 1 0 0 1 wiggle z 0.5 3 restitution 0.9")
    w = j["shaped_walls"][0]
    assert w["wall"] == "plane 0 0 1 0 0 1 wiggle z 0.5 3 restitution 0.9"
    assert w["collisions"] > 100 and w["work"] > 0
    taken = j["dissipated_energy_normal"] + j["dissipated_energy_tangential"]
    assert j["dissipated_energy"] + j["wall_work"] == pytest.approx(taken, rel=1e-9)


def test_an_elastic_gas_under_a_piston_gains_what_the_piston_does(hs):
    # A piston moving down at 0.05 into an elastic gas: every collision with it is elastic, so
    # the wall's work is the gas's whole energy gain; each bounce off a plane moving at -u adds
    # 2 m u (u + |v_n|) > 0, so the work is positive and no sphere is left behind the piston.
    j = run_json(hs, "--n", 200, "--box", 20, "--boundary", "w", "--dt", 0.01, "--steps", 2000, "--seed", 3,
                 "--wall", "plane 0 0 19 0 0 -1 translate 0 0 -0.05")
    assert j["shaped_walls"][0]["collisions"] > 50
    assert j["wall_work"] > 0
    assert -j["dissipated_energy"] == pytest.approx(j["wall_work"], rel=1e-9)


@pytest.mark.parametrize("spec,needles", [
    ("plane 0 0 1 0 0 1 wiggle q 1 2", ["expects wiggle's axis (x, y or z), got 'q'"]),
    ("plane 0 0 1 0 0 1 wiggle z 1 0", ["wiggle period 0 must be > 0"]),
    ("plane 0 0 1 0 0 1 wiggle z 1 -2", ["wiggle period -2 must be > 0"]),
    ("plane 0 0 1 0 0 1 wiggle z -1 2", ["wiggle amplitude -1 must be >= 0"]),
    ("plane 0 0 1 0 0 1 wiggle z 1", ["expects wiggle's period P at its end"]),
    ("plane 0 0 1 0 0 1 translate 0 0 inf", ["translate component inf must be finite"]),
    ("sphere 10 10 10 3 wiggle z 1 2", ["wiggle takes a plane or an unbounded cylinder"]),
    ("cylinder z 10 10 5 wiggle x 1 2", ["wiggle x moves a cylinder across its axis"]),
    ("cylinder z 10 10 5 bounds 2 8 wiggle z 1 2", ["with bounds"]),
    ("plane 0 0 1 0 0 1 time nan", ["time nan must be finite"]),
])
def test_bad_motions_are_refused(hs, spec, needles):
    refused(run(hs, *BOX, "--wall", spec), f"--wall '{spec}'", *needles)


def test_a_sphere_overlapping_a_moving_wall_at_its_start_is_refused(hs, tmp_path):
    # The plate starts at z = 0 + 0.4 * 3 (time 3, translate 0.4): the sphere at 1 overlaps it.
    data = one_sphere(tmp_path, 1)
    refused(run(hs, "--read-data", data, "--boundary", "p,p,w", "--steps", 1,
                "--wall", "plane 0 0 0 0 0 1 translate 0 0 0.4 time 3"),
            "one.data", "overlaps --wall 'plane 0 0 0 0 0 1 translate 0 0 0.4 time 3' (where it is at its time 3)")
    run_json(hs, "--read-data", data, "--boundary", "p,p,w", "--steps", 1, "--wall", "plane 0 0 0 0 0 1 translate 0 0 0.4")


def test_the_event_engine_refuses_moving_walls(hs):
    refused(run(hs, "--n", 40, "--box", 20, "--boundary", "w", "--engine", "event", "--time", 1,
                "--wall", "plane 0 0 1 0 0 1 wiggle z 0.1 1"), "shaped walls run in the stepper only")


def test_a_continued_run_keeps_the_walls_phase_with_time(hs, tmp_path):
    # 300 steps at once equal 100 steps, then 200 from the state written with 'time 1' (100 dt):
    # the wiggled plate is where and how fast the first run left it.
    data = one_sphere(tmp_path, 3, -1)
    wall = "plane 0 0 0.5 0 0 1 wiggle z 0.3 0.7 restitution 0.8"
    common = ["--boundary", "p,p,w", "--gravity", "0,0,-1", "--dt", 0.01]
    whole, half, rest = tmp_path / "whole.data", tmp_path / "half.data", tmp_path / "rest.data"
    run_json(hs, "--read-data", data, *common, "--steps", 300, "--wall", wall, "--write-data", whole)
    run_json(hs, "--read-data", data, *common, "--steps", 100, "--wall", wall, "--write-data", half)
    run_json(hs, "--read-data", half, *common, "--steps", 200, "--wall", wall + " time 1", "--write-data", rest)
    atoms = lambda p: [float(x) for x in p.read_text().split("Atoms")[1].split("\n\n")[1].split()[4:]]
    assert atoms(rest) == pytest.approx(atoms(whole), abs=1e-9)


def test_a_plate_wiggled_within_one_step_does_not_miss_the_sphere(hs, tmp_path):
    # A plate with period P = dt is back at 0 at every step's end, the sphere 0.02 above it at
    # rest both times: the plate meets it mid-step where A (1 - cos t) = 0.02 (cos 0.6, sin 0.8)
    # at u = A omega 0.8, and the elastic bounce off it leaves at 2 u = 16 pi. On main's detection
    # of the end overlap alone, no contact.
    data = one_sphere(tmp_path, 0.52)
    out = tmp_path / "out.data"
    j = run_json(hs, "--read-data", data, "--boundary", "p,p,w", "--steps", 3, "--dt", 0.01,
                 "--wall", "plane 0 0 0 0 0 1 wiggle z 0.05 0.01", "--write-data", out)
    assert j["shaped_walls"][0]["collisions"] == 1
    vz = float(out.read_text().split("Velocities")[1].split()[3])
    assert vz == pytest.approx(16 * math.pi, rel=1e-9)
