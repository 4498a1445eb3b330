import os
import subprocess

import pytest


def pytest_addoption(parser):
    parser.addoption("--hardsphere", action="store", default=None,
                     help="path of the built hardsphere program (the tests that compare with it skip without)")


@pytest.fixture(scope="session")
def exe(request):
    path = request.config.getoption("--hardsphere")
    if not path:
        pytest.skip("no --hardsphere program given")
    return os.path.abspath(path)


@pytest.fixture(scope="session")
def cli(exe):
    """Runs `hardsphere ARGS`; returns the CompletedProcess (text)."""
    def run(*args, check=True):
        return subprocess.run([exe, *map(str, args)], capture_output=True, text=True, check=check)
    return run


def cli_error(proc):
    """The CLI's refusal text without its 'hardsphere: error: ' prefix."""
    assert proc.returncode == 2, proc.stderr
    line = proc.stderr.strip().splitlines()[-1]
    assert line.startswith("hardsphere: error: "), line
    return line[len("hardsphere: error: "):]
