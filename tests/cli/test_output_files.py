"""Output files: two outputs naming one file (under any spelling) are refused before anything is
created, a run killed by any terminating signal removes its temporary files and dies by that
signal, and a run whose summary cannot be written leaves no file.
"""
import os
import resource
import signal
import subprocess
import time

import pytest

from hs_run import run


@pytest.mark.parametrize("first,second", [
    ("x", "x"),
    ("x", "./x"),
    ("x", "sub/../x"),
    ("x", "link"),        # a symlink to x (x does not exist yet)
    ("x", "{abs}/x"),
    ("sub/y", "linkdir/y"),  # a symlink to the directory sub
])
@pytest.mark.parametrize("options", [("--json", "--write-data"), ("--json", "--dump"), ("--dump", "--write-data")])
def test_two_outputs_naming_one_file_are_refused(hs, tmp_path, first, second, options):
    (tmp_path / "sub").mkdir()
    os.symlink("x", tmp_path / "link")
    os.symlink("sub", tmp_path / "linkdir")
    before = sorted(os.listdir(tmp_path))
    second = second.format(abs=tmp_path)
    p = run(hs, "--n", 20, "--phi", 0.1, "--steps", 1, options[0], first, options[1], second, cwd=tmp_path)
    assert p.returncode == 2, (p.returncode, p.stderr)
    assert "same file" in p.stderr and options[0] in p.stderr and options[1] in p.stderr, p.stderr
    assert sorted(os.listdir(tmp_path)) == before and os.listdir(tmp_path / "sub") == []


def test_outputs_that_cannot_be_files_are_refused_up_front(hs, tmp_path):
    (tmp_path / "d").mkdir()
    for args, needle in [(["--write-data", "d"], "is a directory"),
                         (["--write-data", "missing/x.data"], "does not exist"),
                         (["--json", "/dev/null"], "not a regular file")]:
        p = run(hs, "--n", 20, "--phi", 0.1, "--steps", 1, *args, cwd=tmp_path)
        assert p.returncode == 2 and needle in p.stderr, (args, p.stderr)
    assert os.listdir(tmp_path) == ["d"] and os.listdir(tmp_path / "d") == []


def test_reading_and_writing_one_data_file_is_allowed(hs, tmp_path):
    assert run(hs, "--n", 20, "--phi", 0.1, "--steps", 0, "--write-data", "s.data", cwd=tmp_path).returncode == 0
    p = run(hs, "--read-data", "s.data", "--steps", 3, "--write-data", "s.data", cwd=tmp_path)
    assert p.returncode == 0, p.stderr
    assert "after 3 steps" in (tmp_path / "s.data").read_text()


def test_an_output_through_a_symlink_writes_its_target(hs, tmp_path):
    os.symlink("target.json", tmp_path / "link.json")
    assert run(hs, "--n", 20, "--phi", 0.1, "--steps", 1, "--json", "link.json", cwd=tmp_path).returncode == 0
    assert os.path.islink(tmp_path / "link.json") and '"n": 20' in (tmp_path / "target.json").read_text()


def default_signals():
    # A child started from a shell without job control may inherit SIGINT ignored; the program
    # rightly keeps an ignored signal ignored, so give it the default disposition a terminal has.
    for s in SIGNALS:
        signal.signal(s, signal.SIG_DFL)


# Every signal a user, a batch system (Slurm and PBS warn with SIGUSR1/SIGUSR2 or SIGALRM before a
# wall-time limit), a closed pipe or abort() may end a run with.
SIGNALS = [signal.SIGTERM, signal.SIGINT, signal.SIGHUP, signal.SIGQUIT, signal.SIGALRM, signal.SIGPIPE,
           signal.SIGUSR1, signal.SIGUSR2, signal.SIGABRT, signal.SIGRTMIN + 3]


@pytest.mark.parametrize("sig", SIGNALS)
def test_a_signal_removes_the_temporary_files_and_kills_with_that_signal(hs, tmp_path, sig):
    cmd = [hs, "run", "--n", 20000, "--phi", 0.2, "--steps", 10 ** 7, "--dump", "t.dump", "--dump-every", 5,
           "--json", "s.json", "--write-data", "f.data"]
    p = subprocess.Popen(list(map(str, cmd)), cwd=tmp_path, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                         preexec_fn=default_signals)
    try:
        deadline = time.monotonic() + 60
        # Wait until the run is under way: the dump's temporary exists and has frames in it.
        while time.monotonic() < deadline:
            tmp = [f for f in os.listdir(tmp_path) if ".tmp." in f]
            if len(tmp) == 2 and (tmp_path / f"t.dump.tmp.{p.pid}").stat().st_size > 0:
                break
            assert p.poll() is None, p.stderr.read()
            time.sleep(0.05)
        else:
            pytest.fail(f"no temporary files after 60 s: {os.listdir(tmp_path)}")
        p.send_signal(sig)
        p.wait(timeout=30)
    finally:
        if p.poll() is None:
            p.kill()
            p.wait()
    assert p.returncode == -sig, p.returncode
    assert os.listdir(tmp_path) == []


@pytest.mark.parametrize("xfsz", ["default", "ignored"])
def test_a_file_size_limit_leaves_no_file(hs, tmp_path, xfsz):
    # Beyond RLIMIT_FSIZE a write raises SIGXFSZ (the program cleans up and dies by it) or, with
    # the signal ignored, fails with EFBIG (seen at the dump frame: exit 2).
    def limit():
        default_signals()
        signal.signal(signal.SIGXFSZ, signal.SIG_DFL if xfsz == "default" else signal.SIG_IGN)
        resource.setrlimit(resource.RLIMIT_FSIZE, (1 << 20, 1 << 20))
    cmd = [hs, "run", "--n", 20000, "--phi", 0.2, "--steps", 100, "--dump", "t.dump", "--dump-every", 10,
           "--json", "s.json"]
    p = subprocess.run(list(map(str, cmd)), cwd=tmp_path, capture_output=True, text=True, preexec_fn=limit, timeout=120)
    if xfsz == "default":
        assert p.returncode == -signal.SIGXFSZ, (p.returncode, p.stderr)
    else:
        assert p.returncode == 2 and "error while writing 't.dump'" in p.stderr, (p.returncode, p.stderr)
    assert os.listdir(tmp_path) == []


def test_a_summary_that_cannot_be_written_leaves_no_output(hs, tmp_path):
    # Standard output closed: the summary fails after the run, and so must the run: exit 2, and the
    # files it would have written are not committed.
    p = subprocess.run([str(hs), "run", "--n", "50", "--phi", "0.1", "--steps", "5", "--write-data", "f.data",
                        "--json", "s.json"], cwd=tmp_path, stderr=subprocess.PIPE, text=True,
                       preexec_fn=lambda: os.close(1))
    assert p.returncode == 2, (p.returncode, p.stderr)
    assert "hardsphere: error: cannot write the summary to standard output" in p.stderr
    assert os.listdir(tmp_path) == []
