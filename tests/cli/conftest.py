import os

import pytest


def pytest_addoption(parser):
    parser.addoption("--hardsphere", action="store", required=True, help="path of the built hardsphere program")


@pytest.fixture(scope="session")
def hs(request):
    return os.path.abspath(request.config.getoption("--hardsphere"))
