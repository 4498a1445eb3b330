"""Callbacks, progress, and Ctrl-C during a run: KeyboardInterrupt between chunks, the engine
left usable."""
import os
import signal
import subprocess
import sys
import textwrap

import numpy as np
import pytest

import hardsphere as hs


@pytest.fixture(scope="module")
def gas():
    return hs.System.random(n=300, phi=0.2, seed=11)


def test_stepper_callback_every_k_steps(gas):
    sim = hs.Stepper(gas)
    seen = []
    sim.run(steps=100, callback=lambda s: seen.append(s.steps), every=30)
    assert seen == [30, 60, 90] and sim.steps == 100


def test_event_callback_every_interval(gas):
    sim = hs.EventEngine(gas)
    seen = []
    sim.run(time=1.0, callback=lambda s: seen.append(s.time), every=0.25)
    assert np.allclose(seen, [0.25, 0.5, 0.75, 1.0], rtol=0, atol=1e-12) and sim.time == 1.0


def test_callback_returning_false_stops(gas):
    sim = hs.Stepper(gas)
    sim.run(steps=100, callback=lambda s: s.steps < 40, every=20)
    assert sim.steps == 40
    ev = hs.EventEngine(gas)
    ev.run(time=1.0, callback=lambda s: False, every=0.1)
    assert abs(ev.time - 0.1) < 1e-12


def test_callback_exception_propagates_and_engine_stays_usable(gas):
    sim = hs.Stepper(gas)

    def boom(s):
        raise RuntimeError("stop here")
    with pytest.raises(RuntimeError, match="stop here"):
        sim.run(steps=50, callback=boom, every=10)
    assert sim.steps == 10
    sim.run(steps=5)
    assert sim.steps == 15


def test_progress_callable_and_bar(gas, capsys):
    sim = hs.Stepper(gas)
    calls = []
    sim.run(steps=20, progress=lambda f, t: calls.append((f, t)))
    assert calls and calls[-1][0] == 1.0 and abs(calls[-1][1] - 0.2) < 1e-12
    assert [f for f, _ in calls] == sorted(f for f, _ in calls)
    sim.run(steps=20, progress=True)  # tqdm, or a line on stderr without it
    hs.EventEngine(gas).run(time=0.2, progress=True)
    assert "100%" in capsys.readouterr().err


CHILD = textwrap.dedent("""
    import sys, hardsphere as hs
    s = hs.System.random(n=2000, phi=0.25, seed=1)
    sim = hs.Stepper(s) if sys.argv[1] == "stepper" else hs.EventEngine(s)
    said = []
    def started(fraction, t):
        if not said:
            said.append(1)
            print("running", flush=True)
    try:
        if sys.argv[1] == "stepper":
            sim.run(steps=10**9, progress=started)
        else:
            sim.run(time=1e6, progress=started)
        print("not interrupted")
    except KeyboardInterrupt:
        t = sim.sim_time
        if sys.argv[1] == "stepper":
            sim.run(steps=10)
        else:
            sim.run(time=0.1)
        ok = sim.sim_time > t and sim.observables()["max_overlap"] == 0
        print("interrupted, ran again" if ok else "broken", flush=True)
""")


@pytest.mark.parametrize("engine", ["stepper", "event"])
def test_sigint_stops_between_chunks(engine):
    env = dict(os.environ)
    # As from a terminal: a shell's background job starts with SIGINT ignored, which Python keeps.
    p = subprocess.Popen([sys.executable, "-c", CHILD, engine], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                         text=True, env=env, preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    assert p.stdout.readline().strip() == "running"
    p.send_signal(signal.SIGINT)
    out, err = p.communicate(timeout=60)
    assert p.returncode == 0, err
    assert out.strip() == "interrupted, ran again"


def test_engine_busy_in_another_thread_is_refused(gas):
    """While one thread runs an engine (GIL released), another thread's access is refused, not a race."""
    import threading
    sim = hs.Stepper(hs.System.random(n=2000, phi=0.25, seed=1))
    stop = threading.Event()
    worker = threading.Thread(target=lambda: sim.run(steps=10**9, callback=lambda s: not stop.is_set(), every=1))
    worker.start()
    refused = 0
    try:
        for _ in range(2000):
            try:
                sim.positions
            except ValueError as e:
                assert str(e) == "the engine is running in another thread; wait for its run() to return"
                refused += 1
                if refused >= 3:
                    break
    finally:
        stop.set()
        worker.join()
    assert refused >= 3
    sim.run(steps=1)  # usable after


# ---- re-entry (issue 42 item 16): a run cannot start, or its measurement restart, inside itself

def reentry_message(cls, method):
    call = f"{cls}.{method}()"
    return (f"{call} called from inside this {cls}'s own run() (its callback or progress function): the run in "
            f"progress would lose its place; return from the callback (returning False stops the run) and call "
            f"{call} after run() returns")


@pytest.mark.parametrize("engine,run,nested,stopped_at", [
    ("Stepper", {"steps": 100, "every": 10}, {"steps": 100}, 10),
    ("EventEngine", {"time": 1.0, "every": 0.1}, {"time": 1.0}, 0.1),
])
def test_run_from_its_own_callback_is_refused(gas, engine, run, nested, stopped_at):
    """Before: the event engine ended at 1.1 with 1 of 10 callbacks, the stepper at 200 steps."""
    sim = getattr(hs, engine)(gas)
    calls = []

    def again(s):
        calls.append(s.sim_time)
        s.run(**nested)
    with pytest.raises(RuntimeError) as err:
        sim.run(callback=again, **run)
    assert str(err.value) == reentry_message(engine, "run")
    assert len(calls) == 1 and abs(sim.sim_time - stopped_at * (0.01 if engine == "Stepper" else 1)) < 1e-12
    sim.run(**nested)  # usable after


@pytest.mark.parametrize("engine,run", [("Stepper", {"steps": 20}), ("EventEngine", {"time": 0.2})])
def test_reset_or_run_from_progress_or_callback_is_refused(gas, engine, run):
    sim = getattr(hs, engine)(gas)
    with pytest.raises(RuntimeError) as err:
        sim.run(progress=lambda f, t: sim.run(**run), **run)
    assert str(err.value) == reentry_message(engine, "run")
    every = {"every": 5} if engine == "Stepper" else {"every": 0.05}
    with pytest.raises(RuntimeError) as err:
        sim.run(callback=lambda s: s.reset_counters(), **every, **run)
    assert str(err.value) == reentry_message(engine, "reset_counters")


@pytest.mark.parametrize("engine,run,every", [("Stepper", {"steps": 40}, 10), ("EventEngine", {"time": 0.4}, 0.1)])
def test_reading_and_writing_from_a_callback_is_allowed(gas, tmp_path, engine, run, every):
    """What reads the state (arrays, observables, files, a System, another engine's run) changes nothing."""
    sim = getattr(hs, engine)(gas)
    other = hs.Stepper(gas)
    seen = []

    def look(s):
        k = len(seen)
        seen.append((s.positions.copy(), s.observables()["collisions"]))
        s.write_data(str(tmp_path / f"{k}.data"))
        s.write_dump(str(tmp_path / f"{k}.dump"))
        dump.write(s)
        s.system()
        other.run(steps=1)
    with hs.DumpWriter(str(tmp_path / "traj.dump")) as dump:
        sim.run(callback=look, every=every, **run)
    assert len(seen) == 4 and other.steps == 4 and dump.frames == 4
    assert np.array_equal(seen[-1][0], sim.positions)
    assert len(os.listdir(tmp_path)) == 9


def test_another_threads_run_during_a_callback_is_refused():
    """Between chunks (in a callback) the run is still in progress: another thread may read the
    state but not run the engine (before, its run interleaved with this one)."""
    import threading
    sim = hs.Stepper(hs.System.random(n=300, phi=0.2, seed=3))
    outcome = []

    def from_other_thread():
        try:
            sim.run(steps=5)
            outcome.append("ran")
        except ValueError as e:
            outcome.append(str(e))
        outcome.append(sim.positions.shape)

    def callback(s):
        t = threading.Thread(target=from_other_thread)
        t.start()
        t.join()
    sim.run(steps=20, callback=callback, every=10)
    assert outcome == ["the engine is running in another thread; wait for its run() to return", (300, 3),
                       "the engine is running in another thread; wait for its run() to return", (300, 3)]
    assert sim.steps == 20
