"""MCMC against exact enumeration on a 5-threat / 5-POI problem, and chain diagnostics."""

import warnings

import numpy as np
import pytest
from poi_problems import make_poi_problem

from bsi_sklearn import BSIClassifier
from bsi_sklearn.diagnostics import split_rhat, total_variation
from bsi_sklearn.mcmc import unique_states


@pytest.fixture(scope="module")
def problem():
    return make_poi_problem(n_demos=50, n_negative=10, seed=11)


@pytest.mark.parametrize("prior", ["linear_chain", "sets_of_chains", "forest"])
@pytest.mark.parametrize("likelihood", ["cb", "ci"])
def test_mcmc_agrees_with_exact(problem, prior, likelihood):
    X, y, roles = problem
    exact = BSIClassifier(prior=prior, likelihood=likelihood, inference="exact",
                          **roles).fit(X, y)
    mcmc = BSIClassifier(prior=prior, likelihood=likelihood, inference="mcmc",
                         random_state=0, **roles).fit(X, y)
    assert mcmc.inference_ == "mcmc"
    tv = total_variation(exact.posterior_, mcmc.posterior_)
    assert tv <= 0.02, tv
    assert np.abs(exact.predict_proba(X) - mcmc.predict_proba(X)).max() <= 0.02
    diag = mcmc.mcmc_diagnostics_
    assert diag["rhat"] < 1.05 and 0 <= diag["acceptance_rate"] <= 1


@pytest.mark.parametrize("prior", ["sets_of_chains", "forest"])
def test_sample_frequencies_converge_to_exact(prior):
    """Plain sample frequencies (not only the reweighted estimate) match exact probabilities."""
    X, y, roles = make_poi_problem(n_demos=8, n_threats=2, n_pois=3, chain=(0, 2), seed=4,
                                   always_violated=(1,))
    exact = BSIClassifier(prior=prior, inference="exact", tol=0.0, **roles).fit(X, y)
    mcmc = BSIClassifier(prior=prior, inference="mcmc", n_samples=20_000, n_chains=2,
                         random_state=1, **roles).fit(X, y)
    freq = dict(zip(mcmc.posterior_.specifications, mcmc.mcmc_diagnostics_["sample_frequencies"]))
    assert total_variation(exact.posterior_, freq) < 0.05


def test_reproducible_and_independent_of_n_jobs(problem):
    X, y, roles = problem
    kw = dict(inference="mcmc", likelihood="ci", n_samples=2000, n_chains=3, random_state=7,
              **roles)
    a = BSIClassifier(n_jobs=1, **kw).fit(X, y)
    b = BSIClassifier(n_jobs=2, **kw).fit(X, y)
    c = BSIClassifier(n_jobs=1, **kw).fit(X, y)
    for other in (b, c):
        assert a.posterior_.specifications == other.posterior_.specifications
        assert np.array_equal(a.posterior_.probabilities, other.posterior_.probabilities)
        assert np.array_equal(a.mcmc_diagnostics_["log_posterior_traces"],
                              other.mcmc_diagnostics_["log_posterior_traces"])
    d = BSIClassifier(n_jobs=1, **{**kw, "random_state": 8}).fit(X, y)
    assert not np.array_equal(a.mcmc_diagnostics_["log_posterior_traces"],
                              d.mcmc_diagnostics_["log_posterior_traces"])


def test_split_rhat():
    rng = np.random.default_rng(0)
    mixed = rng.normal(size=(4, 1000))
    assert split_rhat(mixed) == pytest.approx(1.0, abs=0.01)
    stuck = mixed + np.arange(4)[:, None] * 5
    assert split_rhat(stuck) > 1.5
    assert split_rhat(np.zeros((4, 100))) == 1.0
    assert split_rhat(np.array([[0.0] * 10, [1.0] * 10])) == np.inf
    assert split_rhat(406.0 + 1e-13 * rng.normal(size=(3, 50))) == 1.0


def test_rhat_warning_when_chains_disagree(problem):
    X, y, roles = problem
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        clf = BSIClassifier(inference="mcmc", likelihood="ci", n_samples=4, burn_in=0,
                            n_chains=4, random_state=3, **roles).fit(X, y)
    if clf.mcmc_diagnostics_["rhat"] > 1.05:
        assert any("R-hat" in str(w.message) for w in caught)
    else:  # pragma: no cover - depends on the draw
        assert not any("R-hat" in str(w.message) for w in caught)


def test_unique_states_merges_runs():
    states = np.array([[0, 1, -1], [1, 0, 0], [0, 1, -1]], dtype=np.int16)
    uniq, counts = unique_states(states, np.array([3, 1, 2]))
    assert uniq.tolist() == [[0, 1, -1], [1, 0, 0]] and counts.tolist() == [5, 1]
