"""The walls' own laws on the command line: --wall-restitution, --wall-tangential-restitution and
--wall-friction (one value, or face=value items) accepted and refused, their JSON keys (absent
with default walls), and the walls' energy closing the budget in both engines."""
import pytest
from hs_run import run, run_json, refused

BED = ["--n", 200, "--box", "10,10,20", "--boundary", "p,p,w", "--gravity", "0,0,-1"]
ROUGH = ["--tangential-restitution", 0.5]


@pytest.mark.parametrize("args,needles", [
    (["--wall-restitution", 0], ["--wall-restitution 0 must be in (0, 1]"]),
    (["--wall-restitution", "zlo=1.5"], ["--wall-restitution zlo=1.5 must be in (0, 1]"]),
    (["--wall-restitution", "x"], ["--wall-restitution 'x': 'x' is not a number"]),
    (["--wall-restitution", "zlo=0.5,bottom=0.5"], ["unknown face 'bottom'"]),
    (["--wall-restitution", "zlo=0.5,zlo=0.6"], ["names face zlo twice"]),
    (["--wall-restitution", "zlo=0.5,0.6"], ["'0.6' is not face=value"]),
    (["--wall-restitution", "xlo=0.5"], ["no wall at xlo (axis x is periodic)"]),
    (["--wall-restitution", "zlo=0.5", "--contact-time", 0], ["--contact-time 0 with a --wall-restitution"]),
    (["--wall-friction", 0.3], ["--wall-friction 0.3 needs rough spheres", "--tangential-restitution"]),
    (["--wall-tangential-restitution", "zlo=0.5"], ["--wall-tangential-restitution zlo=0.5 needs rough spheres"]),
    ([*ROUGH, "--wall-tangential-restitution", 1.5], ["--wall-tangential-restitution 1.5 must be in [-1, 1]"]),
    ([*ROUGH, "--wall-friction", "zhi=-1"], ["--wall-friction zhi=-1 must be >= 0"]),
    ([*ROUGH, "--wall-tangential-restitution", -1, "--wall-friction", 0.3],
     ["--wall-friction 0.3 needs a --wall-tangential-restitution above -1"]),
])
def test_bad_wall_options_are_refused(hs, args, needles):
    refused(run(hs, *BED, "--steps", 1, *args), *needles)


def test_wall_options_in_a_box_without_walls_are_refused(hs):
    refused(run(hs, "--n", 100, "--steps", 1, "--wall-restitution", 0.5), "the box has no walls")


@pytest.mark.parametrize("engine", [["--steps", 300], ["--engine", "event", "--time", 3]])
def test_wall_json_keys_and_energy_budget(hs, engine):
    plain = run_json(hs, *BED, *engine)
    assert "wall_laws" not in plain and "wall_dissipated_energy_normal" not in plain
    j = run_json(hs, *BED, *engine, *ROUGH, "--restitution", 0.9, "--wall-restitution", "zlo=0.5",
                 "--wall-tangential-restitution", 0, "--wall-friction", "zlo=0.2")
    assert j["wall_laws"] == {"zlo": {"restitution": 0.5, "tangential_restitution": 0.0, "friction": 0.2},
                              "zhi": {"restitution": 1.0, "tangential_restitution": 0.0, "friction": None}}
    assert j["contact_time"] == 1e-4  # inelastic walls take the TC model's default contact time
    assert j["wall_dissipated_energy_normal"] > 0 and j["wall_dissipated_energy_tangential"] > 0
    # The walls' channels are part of the totals, which close the budget.
    assert j["dissipated_energy_normal"] >= j["wall_dissipated_energy_normal"]
    assert j["dissipated_energy_normal"] + j["dissipated_energy_tangential"] == pytest.approx(
        j["dissipated_energy"], rel=1e-9)
