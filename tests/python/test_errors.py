"""Every refusal class of the CLI raises with the CLI's message: ValueError for bad values and
malformed files (with file:line), OSError for files that cannot be read or written."""
import os

import pytest

import hardsphere as hs
from conftest import cli_error


@pytest.fixture(scope="module")
def gas():
    return hs.System.random(n=100, phi=0.1, seed=1)


@pytest.fixture(scope="module")
def gas_file(tmp_path_factory, gas):
    p = tmp_path_factory.mktemp("e") / "gas.data"
    gas.write_data(str(p))
    return str(p)


def same(cli_text, py_text, *names):
    """The CLI's text with its option names as the keywords (--contact-time -> contact_time)."""
    for n in names:
        cli_text = cli_text.replace("--" + n, n.replace("-", "_"))
    assert py_text == cli_text


@pytest.mark.parametrize("engine", [hs.Stepper, hs.EventEngine])
@pytest.mark.parametrize("e", [1.5, 0.0, -0.2])
def test_bad_restitution(cli, gas_file, gas, engine, e):
    with pytest.raises(ValueError) as err:
        engine(gas, restitution=e)
    same(cli_error(cli("run", "--read-data", gas_file, "--restitution", e, check=False)), str(err.value),
         "restitution")


def test_bad_contact_time(cli, gas_file, gas):
    with pytest.raises(ValueError) as err:
        hs.Stepper(gas, restitution=0.9, contact_time=-1.0)
    same(cli_error(cli("run", "--read-data", gas_file, "--restitution", 0.9, "--contact-time", -1, check=False)),
         str(err.value), "restitution", "contact-time")


@pytest.mark.parametrize("engine", [hs.Stepper, hs.EventEngine])
def test_gravity_along_periodic_axis_warns(cli, gas_file, gas, engine):
    # A chute that cannot settle runs, with the CLI's warning as a UserWarning.
    with pytest.warns(UserWarning) as w:
        sim = engine(gas, gravity=(0, 0, -1))
    text = cli("run", "--read-data", gas_file, "--gravity", "0,0,-1", "--steps", 1, "--quiet", check=False).stderr
    assert text.startswith("hardsphere: warning: ")
    cli_text = text.splitlines()[0][len("hardsphere: warning: "):]
    for n in ("gravity", "wall-tangential-restitution", "wall-friction"):
        cli_text = cli_text.replace("--" + n, n.replace("-", "_"))
    assert str(w[0].message) == cli_text
    assert sim.gravity == [0, 0, -1]


@pytest.mark.parametrize("engine", [hs.Stepper, hs.EventEngine])
def test_gravity_set_between_runs(engine):
    # A free sphere: each run's flights are parabolas of the gravity set before it.
    one = hs.System(hs.Box(10, "w"), positions=[[1.0, 2.0, 3.0]], velocities=[[0.5, 0, 0]])
    sim = engine(one, gravity=(0, 0, -1), **({"dt": 0.01} if engine is hs.Stepper else {}))
    run = (lambda s: s.run(steps=10)) if engine is hs.Stepper else (lambda s: s.run(time=0.1))
    run(sim)
    sim.gravity = (0.6, 0, 0.8)
    assert sim.gravity == [0.6, 0, 0.8]
    run(sim)
    assert sim.velocities[0] == pytest.approx([0.5 + 0.06, 0, -0.1 + 0.08], abs=1e-12)
    assert sim.observables()["gravity_changed"] is True
    with pytest.raises(ValueError, match="gravity component y = nan must be finite"):
        sim.gravity = (0, float("nan"), 0)
    assert sim.gravity == [0.6, 0, 0.8]


@pytest.mark.parametrize("dt", [0.0, -0.01])
def test_bad_dt(cli, gas_file, gas, dt):
    with pytest.raises(ValueError) as err:
        hs.Stepper(gas, dt=dt)
    assert str(err.value) == cli_error(cli("run", "--read-data", gas_file, "--dt", dt, "--steps", 1, check=False))
    # The CLI's parser refuses a NaN before the stepper sees it; here the stepper does.
    with pytest.raises(ValueError, match="time step dt = nan must be positive and finite"):
        hs.Stepper(gas, dt=float("nan"))


def test_unreadable_data_file(cli, tmp_path):
    missing = str(tmp_path / "missing.data")
    with pytest.raises(OSError) as err:
        hs.System.from_data(missing)
    assert str(err.value) == cli_error(cli("run", "--read-data", missing, check=False))
    assert "cannot open data file" in str(err.value)
    with pytest.raises(OSError) as err:
        hs.System.from_data(str(tmp_path))
    assert str(err.value) == cli_error(cli("run", "--read-data", tmp_path, check=False))


def test_malformed_data_file(cli, gas_file, tmp_path):
    bad = tmp_path / "bad.data"
    lines = open(gas_file).read().splitlines()
    atoms = next(i for i, line in enumerate(lines) if line.startswith("Atoms"))
    lines[atoms + 2] = "1 1 1.0 x 0 0 0"  # a row with a non-number
    bad.write_text("\n".join(lines) + "\n")
    with pytest.raises(ValueError) as err:
        hs.System.from_data(str(bad))
    assert str(err.value) == cli_error(cli("run", "--read-data", bad, check=False))
    assert str(err.value).startswith(f"{bad}:{atoms + 3}: ")


def test_overlapping_spheres(cli, tmp_path):
    box = hs.Box(10.0)
    with pytest.raises(ValueError, match="overlap"):
        hs.System(box, [[1, 1, 1], [1.5, 1, 1]])
    # The same pair in a data file: the CLI's and the module's reader say the same.
    good = hs.System(box, [[1, 1, 1], [3, 1, 1]])
    path = tmp_path / "pair.data"
    good.write_data(str(path))
    text = path.read_text().replace("3 1 1", "1.5 1 1", 1)
    assert text != path.read_text()
    path.write_text(text)
    with pytest.raises(ValueError) as err:
        hs.System.from_data(str(path))
    assert str(err.value) == cli_error(cli("run", "--read-data", path, check=False))


def test_bad_run_lengths(gas):
    sim = hs.Stepper(gas)
    with pytest.raises(ValueError, match="steps = -1 must be >= 0"):
        sim.run(steps=-1)
    with pytest.raises(ValueError, match="give one"):
        sim.run(steps=1, time=1.0)
    ev = hs.EventEngine(gas)
    with pytest.raises(ValueError, match="stepper option"):
        ev.run(steps=10)
    with pytest.raises(ValueError, match="must be positive and finite"):
        ev.run(time=-1.0)
    with pytest.raises(ValueError, match="unknown|expected"):
        hs.Stepper(gas, detect="sideways")


def test_bad_init(cli):
    with pytest.raises(ValueError) as err:
        hs.System.random(n=100, phi=0.7)
    assert str(err.value) == cli_error(cli("run", "--n", 100, "--phi", 0.7, check=False))
    with pytest.raises(ValueError) as err:
        hs.System.random(n=500, phi=0.35, method="random")
    assert str(err.value) == cli_error(cli("run", "--n", 500, "--phi", 0.35, "--init", "random", check=False))
    with pytest.raises(ValueError) as err:
        hs.System.random(n=0)
    assert str(err.value) == "number of particles n = 0 must be >= 1"
    with pytest.raises(ValueError, match="unknown init method 'hexagonal'"):
        hs.System.random(n=10, method="hexagonal")


def test_unwritable_outputs_leave_nothing(gas, tmp_path):
    sim = hs.Stepper(gas)
    with pytest.raises(OSError):
        sim.write_data(str(tmp_path / "no" / "such" / "dir.data"))
    with pytest.raises(OSError):
        sim.write_dump(str(tmp_path))  # a directory
    sim.write_data(str(tmp_path / "ok.data"))
    sim.write_dump(str(tmp_path / "ok.dump"))
    assert sorted(os.listdir(tmp_path)) == ["ok.data", "ok.dump"]  # no temporaries left


@pytest.mark.parametrize("engine,length,cli_args", [
    (hs.Stepper, {"steps": 2 * 10**13}, ["--steps", 2 * 10**13]),
    (hs.EventEngine, {"time": 1e13}, ["--engine", "event", "--time", 1e13]),
])
def test_run_over_work_limit_refused_up_front(cli, gas_file, gas, engine, length, cli_args):
    """The CLI's up-front refusal (default limit 1e15), before anything runs."""
    sim = engine(gas)
    with pytest.raises(ValueError) as err:
        sim.run(**length)
    assert str(err.value) == cli_error(cli("run", "--read-data", gas_file, *cli_args, check=False))
    assert sim.sim_time == 0 and sim.observables()["collisions"] == 0


def test_work_limit_keyword():
    gas = hs.System.random(n=100, phi=0.1, seed=1)
    with pytest.raises(ValueError, match=r"^the run would take 1000 particle-steps \(100 spheres, 10 steps\), "
                                         r"more than the limit of 999; use fewer steps$"):
        hs.Stepper(gas, work_limit=999).run(steps=10)
    hs.Stepper(gas, work_limit=1000).run(steps=10)
    # Past the up-front bound, the engine's own limit names the end of the requested run, not of
    # the chunk the run loop was in (the first chunk ends at 3/4 of it).
    ev = hs.EventEngine(gas, work_limit=1200)  # bound 1096, the run 1440
    with pytest.raises(ValueError, match=r"^event engine: the run needs more than 1200 events \(it had reached "
                                         r"time [0-9.e-]+ of 5\); shorten the run$"):
        ev.run(time=5.0)


def test_bad_blocks(gas):
    ev = hs.EventEngine(gas)
    with pytest.raises(ValueError, match="blocks = 0 must be >= 1"):
        ev.run(time=1.0, blocks=0)
    with pytest.raises(ValueError, match="blocks = 1000001 is more than 1000000"):  # the CLI's --blocks bound
        ev.run(time=1.0, blocks=1000001)
    with pytest.raises(TypeError):
        hs.Stepper(gas).run(steps=1, blocks=2)  # an event-engine option


@pytest.mark.parametrize("engine", [hs.Stepper, hs.EventEngine])
@pytest.mark.parametrize("limit,shown", [(0, "0"), (-1.0, "-1"), (float("nan"), "nan"), (float("inf"), "inf")])
def test_work_limit_must_be_positive_and_finite(gas, engine, limit, shown):
    """A NaN or infinite limit is no limit; 0 was refused as "max_events must be positive"."""
    with pytest.raises(ValueError) as err:
        engine(gas, work_limit=limit)
    assert str(err.value) == (f"work_limit {shown} must be positive and finite "
                              "(the most particle-steps or events a run may take)")


@pytest.mark.parametrize("engine", [hs.Stepper, hs.EventEngine])
def test_inertia_on_smooth_spheres_is_refused(gas, engine):
    with pytest.raises(ValueError, match="inertia"):
        engine(gas, inertia=0.5)


@pytest.mark.parametrize("engine", [hs.Stepper, hs.EventEngine])
def test_resting_time_without_gravity_is_refused(gas, engine):
    with pytest.raises(ValueError, match="resting_time"):
        engine(gas, resting_time=0.3)
