"""Shared fixtures: small synthetic problems written independently of the library."""

import pytest
from poi_problems import make_poi_problem


@pytest.fixture(scope="session")
def poi_problem():
    return make_poi_problem()
