"""Kinematic spheres from Python: System.from_data(..., kinematic_types=[2]) as --kinematic-types 2,
a Stepper run equal to the CLI's bit for bit (with its kinematic_* keys), and the refusals."""
import json

import numpy as np
import pytest

import hardsphere as hs

from test_cli_agreement import KEYS

from tests.frozen_bed import write_bed


def test_stepper_with_kinematic_base_equals_cli(cli, tmp_path):
    data = write_bed(tmp_path / "bed.data", (0.2, 0, 0))
    out = tmp_path / "cli.data"
    summary = json.loads(cli("run", "--read-data", data, "--boundary", "p,p,w", "--gravity", "0,0,-1",
                             "--restitution", 0.6, "--kinematic-types", 2, "--steps", 500, "--dt", 0.005,
                             "--json", "-", "--write-data", out).stdout)
    sim = hs.Stepper(hs.System.from_data(str(data), boundary="p,p,w", kinematic_types=[2]), dt=0.005,
                     gravity=(0, 0, -1), restitution=0.6)
    sim.run(steps=500)
    o = sim.observables()
    for k in KEYS:
        assert (k in o) == (k in summary), k
        if k in summary:
            assert o[k] == summary[k], k
    # The base's touching spheres may overlap by rounding once they move: read as kinematic.
    final = hs.System.from_data(str(out), boundary="p,p,w", kinematic_types=[2])
    for f in ("ids", "positions", "velocities", "images"):
        assert np.array_equal(getattr(final, f), getattr(sim, f)), f
    for k in ("kinematic_spheres", "kinematic_collisions", "kinematic_work"):
        assert o[k] == summary[k], k
    assert o["kinematic_spheres"] == 36 and o["kinematic_work"] != 0  # the moving base did work


@pytest.mark.parametrize("types,text", [
    ([3], "kinematic_types 3: no atom of type 3 in"),
    ([0], "kinematic_types"),
    ([2, 2], "kinematic_types: type 2 is given twice"),
    ("2", "kinematic_types takes a sequence of atom types"),
])
def test_bad_kinematic_types_are_refused(tmp_path, types, text):
    with pytest.raises(ValueError, match=text):
        hs.System.from_data(str(write_bed(tmp_path / "bed.data")), boundary="p,p,w", kinematic_types=types)


def test_the_event_engine_refuses_kinematic_spheres(tmp_path):
    s = hs.System.from_data(str(write_bed(tmp_path / "bed.data")), boundary="p,p,w", kinematic_types=[2])
    with pytest.raises(ValueError, match="run them with the stepper"):
        hs.EventEngine(s)
