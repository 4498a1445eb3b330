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
    p = subprocess.Popen([sys.executable, "-c", CHILD, engine], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                         text=True, env=env)
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
