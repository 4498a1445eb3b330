"""run(transport=True) from Python: D, eta and lambda equal to the CLI's --transport bit for bit in
both engines, the keys gone after a run without it, and the refusals with the CLI's messages."""
import json

import pytest

import hardsphere as hs

KEYS = ["diffusion", "diffusion_error", "diffusion_raw", "diffusion_raw_error", "shear_viscosity",
        "shear_viscosity_error", "thermal_conductivity", "thermal_conductivity_error", "transport_blocks",
        "transport_window", "transport_sample_interval", "transport_temperature"]
STATE = ["--n", 256, "--phi", 0.25, "--seed", 3, "--transport", "--transport-window", 1]


def gas():
    return hs.System.random(n=256, phi=0.25, seed=3)


@pytest.mark.parametrize("engine", ["stepper", "event"])
def test_equal_to_the_cli(cli, engine):
    if engine == "event":
        sim = hs.EventEngine(gas()).run(time=20, transport=True, transport_window=1)
        args = ["--engine", "event", "--time", 20]
    else:
        sim = hs.Stepper(gas(), dt=0.01).run(steps=2000, transport=True, transport_window=1)
        args = ["--dt", 0.01, "--steps", 2000]
    ref = json.loads(cli("run", *STATE, *args, "--json", "-").stdout)
    got = sim.observables()
    for key in KEYS:
        assert got[key] == ref[key], key


def test_keys_only_after_a_complete_transport_run():
    sim = hs.Stepper(gas(), dt=0.01)
    assert "shear_viscosity" not in sim.observables()
    sim.run(steps=2000, transport=True, transport_window=1)
    assert sim.observables()["transport_blocks"] == 10
    sim.run(steps=10)
    assert "shear_viscosity" not in sim.observables()


@pytest.mark.parametrize("kwargs,text", [
    (dict(transport=True, transport_window=-1.0), "transport_window -1 must be positive and finite"),
    (dict(transport_window=1.0), "transport_window and transport_blocks need transport=True"),
    (dict(transport=True, transport_blocks=1), "transport_blocks 1 must be 2 to 100000"),
    (dict(transport=True), "transport=True: the measured run of time 1 is too short"),
])
def test_refusals(kwargs, text):
    with pytest.raises(ValueError, match=text.replace("(", r"\(")):
        hs.Stepper(gas(), dt=0.01).run(steps=100, **kwargs)


def test_scenes_without_coefficients_are_refused():
    s = hs.System.random(n=100, phi=0.1, seed=1)
    with pytest.raises(ValueError, match="restitution 0.9"):
        hs.Stepper(s, dt=0.01, restitution=0.9).run(steps=20000, transport=True)
