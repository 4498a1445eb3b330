"""Temporaries of hs.DumpWriter (and of write_data) never survive the process: every terminating
signal removes them and the process still dies by that signal; Ctrl-C stays KeyboardInterrupt and
handlers set with signal.signal still run (issue 42 item 13, docs/python.md). Each case runs in a
child process."""
import os
import signal
import subprocess
import sys
import textwrap

import pytest

import hardsphere as hs

# The children run in their own directories: the package's location, not a relative PYTHONPATH.
ENV = dict(os.environ, PYTHONPATH=os.pathsep.join([os.path.dirname(os.path.dirname(hs.__file__)),
                                                   os.environ.get("PYTHONPATH", "")]))

CHILD = textwrap.dedent("""
    import resource, signal, sys, time
    import hardsphere as hs
    resource.setrlimit(resource.RLIMIT_CORE, (0, 0))   # SIGQUIT dumps core by default
    where, handler = sys.argv[1], sys.argv[2]
    handled = []
    def note(sig, frame):
        handled.append(sig)
        print("handled", flush=True)
    if handler == "before":
        signal.signal(signal.SIGTERM, note)
    if handler == "exit":
        signal.signal(signal.SIGTERM, lambda sig, frame: sys.exit(3))
    sim = hs.Stepper(hs.System.random(n=2000, phi=0.25, seed=1))
    dump = hs.DumpWriter("traj.dump")
    dump.write(sim)
    if handler == "after":
        signal.signal(signal.SIGTERM, note)
    said = []
    def started(fraction, t):
        if not said:
            said.append(1)
            print("ready", flush=True)
    if where == "sleep":
        print("ready", flush=True)
        time.sleep(60)
    elif handler in ("none", "exit"):
        sim.run(steps=10**9, progress=started)       # in C++, the GIL released
    else:
        # The handler runs between chunks; the run goes on until it has.
        sim.run(steps=10**9, callback=lambda s: not handled, every=1, progress=started)
        dump.close()
        print("closed", flush=True)
""")


def run_child(tmp_path, sig, where, handler="none"):
    # As from a terminal: a shell's background job starts with SIGINT ignored, which is kept.
    p = subprocess.Popen([sys.executable, "-c", CHILD, where, handler], cwd=tmp_path, env=ENV,
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                         preexec_fn=lambda: signal.signal(sig, signal.SIG_DFL))
    assert p.stdout.readline().strip() == "ready"
    p.send_signal(sig)
    out, err = p.communicate(timeout=60)
    return p.returncode, out, err


TERMINATING = [signal.SIGTERM, signal.SIGHUP, signal.SIGUSR1, signal.SIGUSR2, signal.SIGALRM, signal.SIGQUIT]


@pytest.mark.parametrize("sig", TERMINATING, ids=lambda s: s.name)
@pytest.mark.parametrize("where", ["sleep", "run"])
def test_terminating_signal_removes_temporaries(tmp_path, sig, where):
    code, out, err = run_child(tmp_path, sig, where)
    assert code == -sig, err  # died by the signal, as without the module
    assert os.listdir(tmp_path) == []


@pytest.mark.parametrize("where", ["sleep", "run"])
def test_ctrl_c_is_still_keyboard_interrupt(tmp_path, where):
    code, out, err = run_child(tmp_path, signal.SIGINT, where)
    assert "KeyboardInterrupt" in err
    assert os.listdir(tmp_path) == []


@pytest.mark.parametrize("handler", ["before", "after"])
def test_user_handler_runs_and_the_writer_stays(tmp_path, handler):
    """A handler set with signal.signal (before or after the writer opened) is called and the
    process goes on: the temporary is still the writer's, committed by close()."""
    code, out, err = run_child(tmp_path, signal.SIGTERM, "run", handler)
    assert code == 0, err
    assert out.split() == ["handled", "closed"]
    assert os.listdir(tmp_path) == ["traj.dump"]


def test_user_handler_that_exits_discards_the_writer(tmp_path):
    """sys.exit from a handler unwinds the run and the interpreter's exit discards the writer."""
    code, out, err = run_child(tmp_path, signal.SIGTERM, "run", "exit")
    assert code == 3, err
    assert os.listdir(tmp_path) == []


FORK = textwrap.dedent("""
    import os, signal, sys
    import hardsphere as hs
    sim = hs.Stepper(hs.System.random(n=100, phi=0.2, seed=1))
    dump = hs.DumpWriter("traj.dump")
    dump.write(sim)
    print("parent", os.getpid(), flush=True)
    pid = os.fork()
    if pid == 0:                       # a child that writes and ends normally
        try:
            dump.write(sim)
        except ValueError as e:
            print(e, flush=True)
        sys.exit(0)
    os.waitpid(pid, 0)
    pid = os.fork()
    if pid == 0:                       # a child killed by a signal
        os.kill(os.getpid(), signal.SIGTERM)
    _, status = os.waitpid(pid, 0)
    assert os.WIFSIGNALED(status) and os.WTERMSIG(status) == signal.SIGTERM
    sim.run(steps=10)
    dump.write(sim)
    dump.close()
    lines = len(open("traj.dump").readlines())
    print("frames", dump.frames, sorted(os.listdir(".")), lines)
""")


def test_forked_child_leaves_the_parents_writer_alone(tmp_path):
    """A forked child inherits the writer: it may not write it, and neither its exit nor its death
    by a signal removes the parent's temporary."""
    p = subprocess.run([sys.executable, "-c", FORK], cwd=tmp_path, env=ENV, capture_output=True, text=True,
                       timeout=60)
    assert p.returncode == 0, p.stderr
    parent, refused, done = p.stdout.splitlines()
    assert refused == (f"DumpWriter 'traj.dump' was opened by process {parent.split()[1]}; "
                       "a forked process cannot write or close it")
    assert done == f"frames 2 ['traj.dump'] {2 * (9 + 100)}"  # nothing written twice by the child
