"""--transport on the command line: the JSON keys of both engines, the two engines agreeing on one
state within their error bars, a dilute gas against Chapman-Enskog, and every refusal."""
import math

import pytest
from hs_run import run, run_json, refused

KEYS = ["diffusion", "diffusion_error", "diffusion_raw", "diffusion_raw_error", "shear_viscosity",
        "shear_viscosity_error", "thermal_conductivity", "thermal_conductivity_error", "transport_blocks",
        "transport_window", "transport_sample_interval", "transport_temperature"]
COEFFS = ["diffusion_raw", "shear_viscosity", "thermal_conductivity"]
DENSE = ["--n", 256, "--phi", 0.25, "--seed", 3, "--transport", "--transport-window", 1]


@pytest.fixture(scope="module")
def dense(hs):
    """The same state (256 spheres at phi 0.25) through both engines, time 40 each."""
    return {"stepper": run_json(hs, *DENSE, "--dt", 0.01, "--steps", 4000),
            "event": run_json(hs, *DENSE, "--engine", "event", "--time", 40)}


def test_keys_of_both_engines(hs, dense):
    for engine, j in dense.items():
        for key in KEYS:
            assert key in j, (engine, key)
        assert j["transport_blocks"] == 10
        assert j["transport_window"] == pytest.approx(1.0)
        for key in COEFFS:
            assert j[key] > 0 and 0 < j[key + "_error"] < 0.5 * j[key], (engine, key, j[key], j[key + "_error"])
        # Yeh-Hummer: D = D_raw + 2.837297 / (6 pi eta L), L = (256 pi / 6 / 0.25)^(1/3)
        length = (256 * math.pi / 6 / 0.25) ** (1 / 3)
        assert j["diffusion"] == pytest.approx(
            j["diffusion_raw"] + 2.837297 / (6 * math.pi * j["shear_viscosity"] * length), rel=1e-12)
    assert "diffusion" not in run_json(hs, "--n", 100, "--steps", 10)


def test_both_engines_agree_within_their_errors(dense):
    # Block errors of 10 blocks: 5 of them apart in quadrature leaves a tail of t(9) below 1e-3.
    a, b = dense["stepper"], dense["event"]
    for key in COEFFS:
        sigma = math.hypot(a[key + "_error"], b[key + "_error"])
        assert abs(a[key] - b[key]) < 5 * sigma, (key, a[key], b[key], sigma)


def test_dilute_gas_against_chapman_enskog(hs):
    # 256 spheres at phi 0.01 (a window of 220, 30 mean free times; 20000 steps of dt 1, ~4 s): D, eta and
    # lambda against Enskog with its converged Sonine factors (1.019, 1.016, 1.025; at phi 0.01
    # Enskog is Chapman-Enskog within 1%). Relative deviations over seeds 1-12 (mean, sd):
    # D -0.0045, 0.0069; eta -0.023, 0.076; lambda +0.028, 0.141 (the block error bars were
    # 0.0069, 0.082, 0.106 of the values: the blocks are independent). Tolerance |mean| + 4 sd.
    j = run_json(hs, "--n", 256, "--phi", 0.01, "--dt", 1, "--steps", 20000, "--seed", 1, "--transport",
                 "--transport-window", 220)
    phi = 0.01
    n, g, b = 6 * phi / math.pi, (1 - phi / 2) / (1 - phi) ** 3, 4 * phi
    theory = {"diffusion_raw": 3 / (8 * n * g) * math.sqrt(1 / math.pi) * 1.019,
              "shear_viscosity": 5 / 16 / math.sqrt(math.pi) * 1.016 * (1 / g + 0.8 * b + 0.7614 * b * b * g),
              "thermal_conductivity": 75 / 64 / math.sqrt(math.pi) * 1.025 * (1 / g + 1.2 * b + 0.7574 * b * b * g)}
    tolerance = {"diffusion_raw": 0.032, "shear_viscosity": 0.33, "thermal_conductivity": 0.60}
    for key, value in theory.items():
        assert abs(j[key] / value - 1) < tolerance[key], (key, j[key], value)


@pytest.mark.parametrize("args,needles", [
    (["--boundary", "p,p,w"], ["--transport", "the z axis has walls"]),
    (["--restitution", 0.9, "--contact-time", 1e-4], ["restitution 0.9"]),
    (["--gravity", "0,0,-1"], ["gravity 0,0,-1"]),
    (["--tangential-restitution", 0.5], ["tangential restitution 0.5"]),
    (["--box", "10,10,12"], ["the box is 10 x 10 x 12"]),
    (["--steps", 100], ["too short", "run at least"]),
    (["--transport-blocks", 1], ["--transport-blocks 1 must be >= 2"]),
    (["--transport-window", 0], ["--transport-window 0 must be positive"]),
    (["--transport-window", "x"], ["--transport-window 'x' is not a number"]),
])
def test_refusals(hs, tmp_path, args, needles):
    out = tmp_path / "s.json"
    size = [] if "--box" in args else ["--phi", 0.1]
    steps = [] if "--steps" in args else ["--steps", 20000]
    p = run(hs, "--n", 200, *size, *steps, "--transport", *args, "--json", out)
    refused(p, *needles)
    assert not out.exists()


def test_options_need_transport(hs):
    for opt in (["--transport-window", 1], ["--transport-blocks", 4]):
        p = run(hs, "--n", 100, "--steps", 10, *opt)
        assert p.returncode == 2 and "--transport" in p.stderr, p.stderr
