"""Session fixtures of the LFE tests: the simulated default dataset is built once."""

import pytest

from lfe import LFEPropositionExtractor, load_lfe_dataset


@pytest.fixture(scope="session")
def default_dataset():
    """The built-in 24-scenario dataset (simulated once per process, then cached)."""
    return load_lfe_dataset()


@pytest.fixture(scope="session")
def default_traces(default_dataset):
    """Paper propositions of every default scenario."""
    return LFEPropositionExtractor().fit_transform(default_dataset.scenarios)
