import pytest


def pytest_addoption(parser):
    parser.addoption("--hardsphere", action="store", required=True, help="path of the built hardsphere program")


@pytest.fixture(scope="session")
def hs(request):
    return request.config.getoption("--hardsphere")
