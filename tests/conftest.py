"""Shared fixtures: small synthetic problems written independently of the library."""

import pytest
from _shared_data import ABSENT, BENCHMARKS_DATA
from poi_problems import make_poi_problem


@pytest.fixture(scope="session")
def poi_problem():
    return make_poi_problem()


def pytest_collection_modifyitems(config, items):
    """Tests marked ``shared_data`` are skipped, with the reason, without the benchmark files."""
    if BENCHMARKS_DATA.is_dir():
        return
    skip = pytest.mark.skip(reason=ABSENT)
    for item in items:
        if item.get_closest_marker("shared_data"):
            # first, so that this reason is reported rather than an empty parameter set's
            item.add_marker(skip, append=False)
