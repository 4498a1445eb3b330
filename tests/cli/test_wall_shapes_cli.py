"""Shaped walls on the command line (--wall SPEC, repeatable): every bad value refused with exit
status 2 naming the wall and the value, the JSON's shaped_walls and wall_work, and a drum's energy
budget (work of the wall = energy change + what the contacts took)."""
import pytest
from hs_run import run, run_json, refused

BOX = ["--n", 40, "--box", 20, "--boundary", "w", "--steps", 5]
ROUGH = ["--tangential-restitution", 0.3]


@pytest.mark.parametrize("spec,needles", [
    ("", ["expects a shape"]),
    ("box 1 2 3", ["unknown shape 'box'"]),
    ("cylinder q 10 10 5", ["expects the cylinder's axis (x, y or z), got 'q'"]),
    ("sphere 10 10 10", ["expects the sphere's radius at its end"]),
    ("sphere 10 10 x 5", ["expects the sphere's centre CX CY CZ, got 'x'"]),
    ("sphere 10 10 10 0", ["radius 0 must be > 0"]),
    ("cylinder z 10 10 -1", ["radius -1 must be > 0"]),
    ("plane 1 1 1 0 0 0", ["normal 0 0 0 has no direction"]),
    ("plane 0 0 1 0 0 1 shear 0 0 2", ["has a part 2 along the normal"]),
    ("plane 0 0 1 0 0 1 axis z", ["'axis' applies to a sphere (its rotation's axis), not a plane"]),
    ("sphere 10 10 10 3 shear 1 0 0", ["'shear' applies to a plane"]),
    ("cylinder z 10 10 5 bounds 4 2", ["bounds 4 2 must have LO < HI"]),
    ("cone z 10 10 5 2 1 3", ["axial extent 5 2 must have LO < HI"]),
    ("cone z 10 10 2 5 0 0", ["radii 0 0 must be >= 0 and not both 0"]),
    ("cone z 10 10 2 5 -1 3", ["radii -1 3 must be >= 0"]),
    ("sphere 10 10 10 3 outside outside", ["'outside' given twice"]),
    ("sphere 10 10 10 3 sticky", ["unknown keyword 'sticky'"]),
    ("sphere 10 10 10 3 restitution 1.5", ["restitution 1.5 must be in (0, 1]"]),
    ("sphere 10 10 10 3 restitution 0", ["restitution 0 must be in (0, 1]"]),
    ("sphere 10 10 10 3 friction 0.5", ["friction needs rough spheres"]),
    ("sphere 10 10 10 3 rotate inf", ["rotate inf must be finite"]),
])
def test_bad_walls_are_refused(hs, spec, needles):
    refused(run(hs, *BOX, "--wall", spec), f"--wall '{spec}'", *needles)


def test_rough_wall_law_values_are_refused(hs):
    refused(run(hs, *BOX, *ROUGH, "--wall", "sphere 10 10 10 3 tangential_restitution 2"),
            "tangential_restitution 2 must be in [-1, 1]")
    refused(run(hs, *BOX, *ROUGH, "--wall", "sphere 10 10 10 3 friction -1"), "friction -1 must be >= 0")


def test_walls_the_scene_cannot_take_are_refused(hs):
    refused(run(hs, "--n", 40, "--box", 20, "--steps", 5, "--wall", "sphere 10 10 10 3 outside"),
            "periodic axis x crosses the sphere")
    refused(run(hs, "--n", 40, "--box", 20, "--boundary", "w,w,p", "--steps", 5, "--wall", "cylinder x 10 10 3"),
            "periodic axis z crosses the cylinder")
    refused(run(hs, "--n", 40, "--box", 20, "--boundary", "p,w,w", "--steps", 5, "--wall", "plane 0 0 1 0 0 1 rotate 1"),
            "periodic axis x runs along the rotating plane, whose surface velocity is not periodic")
    refused(run(hs, "--n", 40, "--box", 20, "--boundary", "w", "--engine", "event", "--time", 1,
                "--wall", "sphere 10 10 10 3"), "shaped walls run in the stepper only")
    refused(run(hs, *BOX, "--init", "lattice", "--wall", "sphere 10 10 10 3 outside"),
            "does not know shaped walls")


def test_a_data_file_sphere_inside_a_wall_is_refused(hs, tmp_path):
    data = tmp_path / "one.data"
    data.write_text("one\n\n1 atoms\n1 atom types\n0 20 xlo xhi\n0 20 ylo yhi\n0 20 zlo zhi\n\n"
                    "Atoms # sphere\n\n1 1 1 1 11 10 10\n")
    refused(run(hs, "--read-data", data, "--boundary", "w", "--steps", 1, "--wall", "sphere 10 10 10 2 outside"),
            "overlaps --wall 'sphere 10 10 10 2 outside' by 1.5")


def test_default_runs_have_no_wall_keys(hs):
    j = run_json(hs, *BOX)
    assert "shaped_walls" not in j and "wall_work" not in j


def test_a_drum_lists_its_walls_and_closes_the_energy_budget(hs):
    # A rough, inelastic bed in a turning drum (axis y) and a funnel below an obstacle: the JSON
    # lists each wall with its contacts and work; work = energy change + dissipation to rounding.
    j = run_json(hs, "--n", 150, "--box", 20, "--boundary", "w", "--gravity", "0,0,-1", *ROUGH,
                 "--restitution", 0.7, "--dt", 0.005, "--steps", 1500,
                 "--wall", "cylinder y 10 10 8 rotate 0.5 restitution 0.6 tangential_restitution 0.2 friction 0.5",
                 "--wall", "sphere 10 10 10 1 outside")
    walls = j["shaped_walls"]
    assert [w["wall"] for w in walls] == [
        "cylinder y 10 10 8 inside rotate 0.5 restitution 0.6 tangential_restitution 0.2 friction 0.5",
        "sphere 10 10 10 1 outside restitution 1"]
    assert walls[0]["collisions"] + walls[0]["resting_contacts"] > 1000 and walls[0]["work"] > 0
    # A wall at rest does no work; a sphere put back on its surface (after a hop ending a hair
    # inside it) gains the potential energy that takes, counted as the wall's.
    assert abs(walls[1]["work"]) < 1e-6 * walls[0]["work"]
    assert j["wall_work"] == pytest.approx(walls[0]["work"] + walls[1]["work"], rel=1e-12)
    taken = j["dissipated_energy_normal"] + j["dissipated_energy_tangential"]
    # dissipated_energy is E0 - E1: with the wall's work, E0 + W - E1 is what the contacts took.
    assert j["dissipated_energy"] + j["wall_work"] == pytest.approx(taken, rel=1e-9)


@pytest.mark.parametrize("wall", ["cylinder y 10 10 8 rotate 0.5 restitution 0.6 tangential_restitution 0.2 friction 0.5",
                                  "sphere 10 10 10 8 restitution 0.5"])
def test_a_state_written_in_a_drum_reads_back(hs, tmp_path, wall):
    # Spheres resting on or sliding along a concave wall end their steps on its surface, not a
    # hair inside it (~v_t^2 dt^2 / 2R, up to 1e-6 here before), which a run reading the state
    # refused as an overlap.
    scene = ["--boundary", "w", "--gravity", "0,0,-1", *ROUGH, "--restitution", 0.7, "--dt", 0.005, "--wall", wall]
    data = tmp_path / "drum.data"
    p = run(hs, "--n", 150, "--box", 20, *scene, "--steps", 1500, "--write-data", data)
    assert p.returncode == 0, p.stderr
    p = run(hs, "--read-data", data, *scene, "--steps", 1)
    assert p.returncode == 0, p.stderr
