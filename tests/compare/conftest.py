import os

import pytest


def pytest_addoption(parser):
    parser.addoption("--hardsphere", action="store", default=os.environ.get("HARDSPHERE"),
                     help="path of the built hardsphere program")


@pytest.fixture(scope="session")
def hs(request):
    path = request.config.getoption("--hardsphere")
    if not path:
        pytest.skip("no --hardsphere program given")
    return os.path.abspath(path)
