"""MCMC against exact enumeration on a 5-threat / 5-POI problem, and chain diagnostics."""

import warnings

import numpy as np
import pytest
from poi_problems import make_poi_problem
from sklearn.exceptions import ConvergenceWarning

from bsi_sklearn import BSIClassifier
from bsi_sklearn.inference.diagnostics import split_rhat, total_variation
from bsi_sklearn.inference.mcmc import unique_states
from bsi_sklearn.inference.policy import InferencePolicy, warn_disagreement


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
        for key in ("log_posterior_traces", "swap_rate", "burn_in_per_chain",
                    "sample_frequencies"):
            assert np.array_equal(a.mcmc_diagnostics_[key], other.mcmc_diagnostics_[key])
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
    assert np.isnan(split_rhat(np.zeros((2, 3))))
    assert split_rhat(np.array([[0.0, -np.inf, 0.0, 0.0]] * 2)) == np.inf


def test_split_rhat_with_huge_offsets():
    """Log posteriors of -1e6 or so: no overflow of rounding noise into a huge ratio."""
    rng = np.random.default_rng(1)
    # Chains constant on different values, up to incremental rounding (an issue-19 fit
    # reported 1.3e14 here): not mixed at all.
    offsets = np.array([[-1413.2073695157058], [-151.42598903504683]])
    noisy = offsets + 1e-12 * rng.normal(size=(2, 1000))
    assert split_rhat(noisy) == np.inf
    assert split_rhat(-1e6 + np.array([[0.0] * 8, [0.5] * 8])) == np.inf
    # Mixed chains far from zero: the same value as without the offset.
    mixed = rng.normal(size=(4, 500))
    assert split_rhat(mixed - 1e5) == pytest.approx(split_rhat(mixed), abs=1e-9)
    # Agreeing constants with rounding noise: mixed.
    assert split_rhat(-1e6 + 1e-10 * rng.normal(size=(4, 100))) == 1.0


def _fit_recording(X, y, **params):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        clf = BSIClassifier(**params).fit(X, y)
    return clf, [w for w in caught if issubclass(w.category, ConvergenceWarning)]


def test_convergence_warning_when_a_chain_misses_mass(problem):
    X, y, roles = problem
    # A fixed ladder (no pilot adapting it): the scenario is the stopping rule's, not the
    # ladder's.
    clf, caught = _fit_recording(X, y, inference="mcmc", likelihood="ci", n_samples=10,
                                 n_chains=4, n_temperatures=7, random_state=0, **roles)
    diag = clf.mcmc_diagnostics_
    # Ten sweeps a chain over a flat posterior: the raw traces look mixed (R-hat < 1.05) and
    # no better optimum exists, but each chain reached (visited, or weighed one block away)
    # only part of the states the chains found between them. (At 30 sweeps each chain
    # reaches all but 2 % of them, and the reported posterior is within TV 0.011 of exact.)
    assert diag["rhat"] < 1.05 and diag["optimum_gap"] <= 0
    assert diag["max_missed_mass"] == diag["missed_mass_per_chain"].max() > 0.05
    assert len(caught) == 1
    message = str(caught[0].message)
    assert "never reached" in message and "Increase n_samples (now 10)" in message
    assert "restrict the roles" in message


def test_convergence_warning_on_split_rhat(problem):
    X, y, roles = problem
    clf, _ = _fit_recording(X, y, inference="mcmc", likelihood="ci", n_samples=200,
                            random_state=0, **roles)
    assert clf.mcmc_diagnostics_["rhat"] < 1.05
    for rhat, n_warnings in [(1.2, 1), (np.inf, 1), (np.nan, 0), (1.05, 0)]:
        clf.mcmc_diagnostics_.update(rhat=rhat, max_missed_mass=0.0)
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            warn_disagreement(clf.mcmc_diagnostics_, InferencePolicy(n_samples=200), 1e6)
        assert len(caught) == n_warnings
        if n_warnings:
            assert caught[0].category is ConvergenceWarning
            assert "split-R-hat" in str(caught[0].message)


def test_no_convergence_warning_when_the_reported_posterior_agrees():
    X, y, roles = make_poi_problem(n_demos=18, n_threats=2, n_pois=4, chain=(0, 2),
                                   n_negative=6, seed=3, always_violated=(1,))
    clf, caught = _fit_recording(X, y, prior="linear_chain", inference="mcmc", n_samples=500,
                                 burn_in=0, n_chains=4, random_state=4, **roles)
    exact = BSIClassifier(prior="linear_chain", inference="exact", tol=0, **roles).fit(X, y)
    diag = clf.mcmc_diagnostics_
    assert diag["rhat"] < 1.05 and diag["max_missed_mass"] < 0.05 and diag["optimum_gap"] <= 0
    assert total_variation(exact.posterior_, clf.posterior_) < 0.01
    assert caught == []
    one, caught = _fit_recording(X, y, inference="mcmc", likelihood="cb", n_samples=10,
                                 n_chains=1, random_state=0, **roles)
    assert one.mcmc_diagnostics_["max_missed_mass"] == 0.0 and caught == []


def test_every_proposition_in_every_role_with_a_huge_support_suggests_roles():
    X = [np.array([[1, 0, 0], [1, 1, 0], [1, 1, 1]])] * 3
    with pytest.warns(UserWarning, match=r"roles='all' all 3 propositions.*global_candidates="):
        warnings.simplefilter("ignore", ConvergenceWarning)
        BSIClassifier(roles="all", max_exact_hypotheses=10, n_samples=20,
                      random_state=0).fit(X)
    with warnings.catch_warnings():
        warnings.simplefilter("error", UserWarning)
        BSIClassifier(max_exact_hypotheses=10, n_samples=20, n_chains=1, subtasks=[1, 2],
                      random_state=0).fit(X)
        BSIClassifier(random_state=0).fit(X)  # exact: no warning


def test_unique_states_merges_runs():
    states = np.array([[0, 1, -1], [1, 0, 0], [0, 1, -1]], dtype=np.int16)
    uniq, counts = unique_states(states, np.array([3, 1, 2]))
    assert uniq.tolist() == [[0, 1, -1], [1, 0, 0]] and counts.tolist() == [5, 1]
