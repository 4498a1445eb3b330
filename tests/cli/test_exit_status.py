"""Exit status contract: every bad command line ends with status 2 and `hardsphere: error: ...`
naming the option and the value (not CLI11's own codes 104-114, not an internal error), --help
with 0. Nothing is created.
"""
import re
import resource
import subprocess

import pytest

from hs_run import run, run_json, refused


def hardsphere(hs, *args, cwd=None, **kw):
    return subprocess.run([hs, *map(str, args)], capture_output=True, text=True, cwd=cwd, timeout=120, **kw)


@pytest.mark.parametrize("args,needles", [
    ([], ["no command"]),
    (["bogus"], ["'bogus'", "run"]),
    (["--frobnicate"], ["'--frobnicate'"]),
    (["run", "--frobnicate", "3"], ["--frobnicate"]),
    (["run", "extra"], ["extra"]),
    (["run", "--n"], ["--n needs a value"]),
    (["run", "--n", "5", "--n", "6"], ["--n is given more than once"]),
    (["run", "--n", "abc"], ["--n 'abc'"]),
    (["run", "--n", "1e3"], ["--n '1e3'"]),
    (["run", "--n", "10.5"], ["--n '10.5'"]),
    (["run", "--n", ""], ["--n ''"]),
    (["run", "--dt", "1x"], ["--dt '1x'"]),
    (["run", "--phi", "1e400"], ["--phi 1e400"]),
    (["run", "--radius", "0x"], ["--radius '0x'"]),
    (["run", "--dump-every", "5"], ["--dump-every requires --dump"]),
    (["run", "--dump", "d", "--dump-every", "0"], ["--dump-every 0"]),
    (["run", "--n", "1000000000000"], ["--n 1000000000000", "134217728"]),
    (["run", "--n", "134217729"], ["--n 134217729"]),
    (["run", "--histogram-bins", "1000000000000"], ["--histogram-bins 1000000000000"]),
    (["run", "--histogram-bins", "0"], ["--histogram-bins 0"]),
    (["run", "--steps", "-5"], ["--steps -5"]),
    (["run", "--steps", "99999999999999999999"], ["--steps '99999999999999999999'"]),
    (["run", "--equilibrate", "-1"], ["--equilibrate -1"]),
    (["run", "--engine", "event", "--time", "1", "--blocks", "0"], ["--blocks 0"]),
    (["run", "--engine", "event", "--time", "1", "--blocks", "99999999999"], ["--blocks 99999999999"]),
    (["run", "--transport", "--transport-blocks", "1"], ["--transport-blocks 1"]),
    (["run", "--transport", "--transport-window", "-2"], ["--transport-window -2"]),
    (["run", "--transport-window", "2"], ["--transport-window", "--transport"]),
    (["run", "--engine", "event", "--time", "nan"], ["--time nan"]),
    (["run", "--cells", "0"], ["--cells '0'"]),
    (["run", "--cells", "2,2,2,"], ["--cells '2,2,2,'"]),
    # A periodic axis of two diameters: the box is the cause, with auto or with the one cell it
    # can have; a user grid too fine for the diameter is the grid's fault.
    (["run", "--n", "40", "--box", "2,10,12"], ["periodic box length 2 (axis x)", "lengthen that axis"]),
    (["run", "--n", "40", "--box", "2,10,12", "--cells", "1,3,3"], ["periodic box length 2 (axis x)"]),
    (["run", "--n", "40", "--box", "10,10,12", "--cells", "12,3,3"], ["cells 12,3,3", "use fewer cells"]),
    (["run", "--box", "10,10,10,"], ["--box '10,10,10,'"]),
    (["run", "--box", "1e999"], ["1e999"]),
    (["run", "--seed", "0x10"], ["--seed '0x10'"]),
    (["run", "--seed", "+5"], ["--seed '+5'"]),
    (["run", "--radius", "1e-200"], ["--radius 1e-200"]),
    (["run", "--write-data", ""], ["--write-data: empty file name"]),
    (["run", "--dump", ""], ["--dump: empty file name"]),
    (["run", "--json", ""], ["--json: empty file name"]),
    (["run", "--read-data", ""], ["--read-data: empty file name"]),
    (["run", "--read-data", "s.data", "--n", "10"], ["--n", "--read-data"]),
])
def test_bad_command_lines_exit_2_with_the_prefix(hs, tmp_path, args, needles):
    p = hardsphere(hs, *args, cwd=tmp_path)
    refused(p, *needles)
    assert list(tmp_path.iterdir()) == []


def test_numbers_are_decimal(hs):
    # CLI11 read "010" as octal 8 and "0x10" as 16.
    assert run_json(hs, "--n", "010", "--phi", 0.1, "--steps", 0)["n"] == 10
    p = run(hs, "--n", "0x10", "--steps", 0)
    refused(p, "--n '0x10'")


@pytest.mark.parametrize("args", [["--help"], ["-h"], ["run", "--help"], ["run", "--n", "5", "--help"]])
def test_help_exits_0(hs, tmp_path, args):
    p = hardsphere(hs, *args, cwd=tmp_path)
    assert p.returncode == 0, p.stderr
    assert "Usage" in p.stdout and p.stderr == ""
    if "run" in args:
        assert "--read-data" in p.stdout


def test_version_exits_0_and_takes_nothing_after_it(hs, tmp_path):
    p = hardsphere(hs, "--version", cwd=tmp_path)
    assert p.returncode == 0 and re.fullmatch(r"hardsphere \d+\.\d+\.\d+\n", p.stdout) and p.stderr == ""
    refused(hardsphere(hs, "--version", "run", cwd=tmp_path), "--version", "'run'")


def limit_memory():
    # A run too large for the machine, without using the machine's memory: cap the address space.
    resource.setrlimit(resource.RLIMIT_AS, (600 << 20, 600 << 20))


def test_a_run_too_large_for_the_memory_is_refused(hs, tmp_path):
    p = hardsphere(hs, "run", "--n", 134217728, "--steps", 1, "--json", "out.json", cwd=tmp_path, preexec_fn=limit_memory)
    refused(p, "not enough memory", "134217728")
    assert list(tmp_path.iterdir()) == []


def stderr_on_a_terminal(hs, *args):
    """Runs `hardsphere run` with stderr on a pseudo-terminal; returns (status, what it wrote there)."""
    import os
    import pty
    master, slave = pty.openpty()
    p = subprocess.Popen([hs, "run", *map(str, args)], stdout=subprocess.DEVNULL, stderr=slave)
    os.close(slave)
    out = b""
    while True:
        try:
            chunk = os.read(master, 4096)
        except OSError:  # the terminal closes with the process
            break
        if not chunk:
            break
        out += chunk
    os.close(master)
    return p.wait(), out.decode()


def test_progress_line_on_a_terminal_only_and_not_with_quiet(hs):
    args = ("--n", 20000, "--phi", 0.3)
    status, text = stderr_on_a_terminal(hs, *args, "--time", 100)  # 10^4 steps: well over 2 s
    assert status == 0 and "% done, simulated time" in text and "s left" in text
    assert text.rstrip(" ").endswith("\r")  # erased at the end
    status, text = stderr_on_a_terminal(hs, *args, "--time", 40, "--quiet")
    assert status == 0 and text == ""
