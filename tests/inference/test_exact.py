"""Exact enumeration against a first-principles posterior, likelihood formulas, marginals."""

import math

import numpy as np
import pytest
from _reference import brute_force_posterior
from poi_problems import make_poi_problem
from sklearn.base import clone

from bsi_sklearn import BSIClassifier
from bsi_sklearn.inference.diagnostics import total_variation
from bsi_sklearn.model.likelihood import (
    default_log_epsilon,
    likelihood_code,
    log_likelihood,
    log_likelihood_reference,
)


@pytest.mark.parametrize("likelihood", ["cb", "ci"])
def test_log_likelihood_kernel_matches_reference(likelihood):
    rng = np.random.default_rng(1)
    for _ in range(50):
        n_conj = int(rng.integers(0, 40))
        y = rng.integers(0, 2, size=12)
        sat = rng.integers(0, 2, size=12).astype(bool)
        if n_conj == 0:
            sat[:] = True
        log_eps = -float(rng.uniform(1, 60))
        ref = log_likelihood_reference(sat, y, n_conj, log_eps, likelihood)
        got = log_likelihood(float((sat & (y == 1)).sum()), float((sat & (y == 0)).sum()),
                             float((y == 1).sum()), float((y == 0).sum()), n_conj, log_eps,
                             likelihood_code(likelihood), np.zeros(0))
        assert got == pytest.approx(ref, rel=1e-12, abs=1e-9)


def test_log_likelihood_no_overflow_for_hundreds_of_conjuncts():
    v = log_likelihood(3.0, 0.0, 3.0, 5.0, 600, -1000.0, 0, np.zeros(0))
    assert np.isfinite(v) and v == pytest.approx(3 * 600 * math.log(2) + 5 * 2.0**-600)
    assert default_log_epsilon(5, 5) == pytest.approx(-4 * math.log(2) * 20)


def small_problem(seed=0, n_negative=4):
    X, y, roles = make_poi_problem(n_demos=6, n_threats=2, n_pois=3, chain=(0, 2),
                                   n_negative=n_negative, seed=seed, always_violated=(1,))
    return X, y, roles


@pytest.mark.parametrize("prior", ["linear_chain", "sets_of_chains", "forest"])
@pytest.mark.parametrize("likelihood", ["cb", "ci"])
def test_exact_matches_first_principles(prior, likelihood):
    X, y, roles = small_problem(seed=3)
    names = list(X[0].columns)
    ref = brute_force_posterior(X, y, names, roles["global_candidates"], roles["subtasks"],
                                roles["conditions"], prior, likelihood)
    clf = BSIClassifier(prior=prior, likelihood=likelihood, inference="exact", tol=0.0,
                        **roles).fit(X, y)
    assert clf.inference_ == "exact"
    assert clf.n_hypotheses_ == len(ref)
    assert total_variation(clf.posterior_, ref) < 1e-9
    best = max(ref, key=ref.get)
    assert ref[clf.map_specification_] == pytest.approx(ref[best], rel=1e-9)
    # clause marginals
    marg = clf.posterior_.clause_marginals()
    for key, value in marg.items():
        expected = sum(p for s, p in ref.items() if key in s.clauses())
        assert value == pytest.approx(expected, abs=1e-9)
    # the paper's vote equals the mass of satisfied specifications
    vote = clone(clf).set_params(vote="satisfaction").fit(X, y).predict_proba(X)[:, 1]
    for i, x in enumerate(X):
        expected = sum(p for s, p in ref.items() if s.satisfied_by(x))
        assert vote[i] == pytest.approx(expected, abs=1e-9)
    # the default predictive: each specification labels with its own flip rate, learned from
    # the v of n training demonstrations it misclassifies as (v + 1) / (n + 2)
    proba = clf.predict_proba(X)[:, 1]
    n = len(X)
    for i, x in enumerate(X):
        expected = 0.0
        for s, p in ref.items():
            v = sum(s.satisfied_by(xj) != bool(yj) for xj, yj in zip(X, y))
            rate = (v + 1) / (n + 2)
            expected += p * ((1 - rate) if s.satisfied_by(x) else rate)
        assert proba[i] == pytest.approx(expected, abs=1e-9)


def test_tol_drops_at_most_tol_and_reports_it():
    X, y, roles = small_problem(seed=5, n_negative=0)
    full = BSIClassifier(inference="exact", tol=0.0, **roles).fit(X, y)
    cut = BSIClassifier(inference="exact", tol=1e-3, **roles).fit(X, y)
    assert len(cut.posterior_) < len(full.posterior_)
    assert 0 < cut.posterior_.dropped_mass <= 1e-3
    assert total_variation(full.posterior_, cut.posterior_) <= 1e-3 + 1e-12
    # marginals still account for the whole support
    assert np.allclose(full.posterior_.clause_marginals(), cut.posterior_.clause_marginals())


def test_user_epsilon_changes_posterior():
    X, y, roles = small_problem(seed=2)
    a = BSIClassifier(inference="exact", **roles).fit(X, y)
    b = BSIClassifier(inference="exact", epsilon=0.2, **roles).fit(X, y)
    assert b.log_epsilon_ == pytest.approx(math.log(0.2))
    assert total_variation(a.posterior_, b.posterior_) > 0.01


def test_clause_matrix_matches_specifications():
    X, y, roles = small_problem(seed=1)
    post = BSIClassifier(inference="exact", **roles).fit(X, y).posterior_
    mat = post.clause_matrix()
    keys = post.clause_keys()
    assert mat.shape == (len(post), len(keys))
    for i, spec in enumerate(post.specifications[:50]):
        assert {k for k, b in zip(keys, mat[i]) if b} == spec.clauses()
    assert np.allclose(post.probabilities @ mat, post.clause_marginals().to_numpy())
