"""Exact inference wherever the bounded engine can finish, whatever the support's size (issue 19).

The structure tables count order structures by dynamic programming over subsets of subtasks;
here the grouped engine is compared with the ungrouped enumeration on posteriors built from
traces (roles given or not, conditions, negatives, propositions that never change), and
``inference="auto"`` is shown to decide by the engine's work count alone.
"""

import contextlib
import warnings

import numpy as np
import pytest
from _exact_checks import _assert_same_posterior
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from sklearn.exceptions import ConvergenceWarning

import bsi_sklearn.inference._budget as _budget
import bsi_sklearn.inference.auto_budget as auto_budget
from bsi_sklearn import BSIClassifier
from bsi_sklearn.data.roles import resolve_roles
from bsi_sklearn.data.traces import check_traces
from bsi_sklearn.inference.exact import ExactWorkExceeded, exact_posterior
from bsi_sklearn.model import make_model
from bsi_sklearn.model.clauses import clause_truth
from bsi_sklearn.model.priors import PRIORS


def _traces(seed, n_props, n_demos):
    """Random 0/1 traces; some propositions hold throughout or never (interchangeable parts)."""
    rng = np.random.default_rng(seed)
    kind = rng.integers(0, 4, n_props)  # 0: random, 1: from some step on, 2: always, 3: never
    X = []
    for _ in range(n_demos):
        T = int(rng.integers(1, 6))
        tr = (rng.random((T, n_props)) < 0.5).astype(np.uint8)
        for p in range(n_props):
            if kind[p] == 1:
                tr[:, p] = np.arange(T) >= rng.integers(0, T + 1)
            elif kind[p] == 2:
                tr[:, p] = 1 if rng.random() < 0.9 else tr[:, p]
            elif kind[p] == 3:
                tr[:, p] = 0 if rng.random() < 0.9 else tr[:, p]
        X.append(tr)
    return X


def _roles(draw_roles, rng, n_props):
    if draw_roles == "none":
        return None, None, None
    props = np.arange(n_props)
    globals_ = sorted(rng.choice(props, int(rng.integers(0, n_props + 1)), replace=False))
    subtasks = sorted(rng.choice(props, int(rng.integers(0, min(n_props, 4) + 1)),
                             replace=False))
    conditions = None
    if draw_roles == "conditions" and subtasks:
        # a subtask is never its own condition (roles.resolve_roles refuses it)
        conditions = {int(w): int(rng.choice([p for p in props if p != w]))
                      for w in subtasks if rng.random() < 0.6 and len(props) > 1}
    return [int(g) for g in globals_], [int(w) for w in subtasks], conditions


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(seed=st.integers(0, 10**6), prior=st.sampled_from(PRIORS),
       likelihood=st.sampled_from(["cb", "ci"]),
       roles=st.sampled_from(["none", "given", "conditions"]), n_props=st.integers(1, 4),
       n_demos=st.integers(1, 40), frac_pos=st.sampled_from([0.5, 0.8, 1.0]),
       epsilon=st.sampled_from([None, 0.05]), tol=st.sampled_from([1e-9, 0.0]))
def test_grouped_equals_ungrouped_from_traces(seed, prior, likelihood, roles, n_props, n_demos,
                                              frac_pos, epsilon, tol):
    rng = np.random.default_rng(seed + 1)
    traces = check_traces(_traces(seed, n_props, n_demos))
    r = resolve_roles(*_roles(roles, rng, n_props), traces.n_props, traces.feature_names)
    truth = clause_truth(traces, r)
    y = (rng.random(n_demos) < frac_pos).astype(np.int64)
    model = make_model(prior=prior, likelihood=likelihood, n_globals=r.n_globals,
                       n_subtasks=r.n_subtasks, epsilon=epsilon, p_part=0.35, n_new=3.0)
    _assert_same_posterior(exact_posterior(truth, y, model, tol=tol),
                           exact_posterior(truth, y, model, tol=tol, grouped=False))


@pytest.mark.parametrize("prior", PRIORS)
@pytest.mark.parametrize("likelihood", ["cb", "ci"])
def test_grouped_equals_ungrouped_with_every_proposition_in_every_role(prior, likelihood):
    traces = check_traces(_traces(7, 5, 40))
    r = resolve_roles(None, None, None, traces.n_props, traces.feature_names)
    y = (np.random.default_rng(3).random(40) < 0.7).astype(np.int64)
    model = make_model(prior=prior, likelihood=likelihood, n_globals=5, n_subtasks=5)
    truth = clause_truth(traces, r)
    _assert_same_posterior(exact_posterior(truth, y, model),
                           exact_posterior(truth, y, model, grouped=False))


def _no_roles_problem(n_demos, n_props=11, seed=0):
    """Missions of 11 propositions and no roles: four safety flags true from the start (broken
    in some unacceptable runs), steps done in order (acceptable) or shuffled, one step rare."""
    rng = np.random.default_rng(seed)
    X, y = [], []
    steps = list(range(4, n_props))
    for _ in range(n_demos):
        ok = rng.random() < 0.6
        tr = np.zeros((12, n_props), dtype=np.uint8)
        tr[:, :4] = 1
        order = steps[:-1] if ok else list(rng.permutation(steps[:-1]))
        for t, s in enumerate(order, start=1):
            if ok or rng.random() < 0.9:
                tr[t:, s] = 1
        if rng.random() < 0.2:
            tr[-1, steps[-1]] = 1
        if not ok and rng.random() < 0.5:
            tr[6:, rng.integers(4)] = 0
        X.append(tr)
        y.append(int(ok))
    return X, np.array(y)


class _Spent:
    """Records the work the exact engine spends (its budget's count)."""

    def __init__(self, monkeypatch):
        self.total = 0.0
        spend = _budget.Budget.spend

        def recording(budget, work, what):
            self.total += work
            return spend(budget, work, what)

        monkeypatch.setattr(_budget.Budget, "spend", recording)


def test_cb_without_roles_is_exact_on_a_huge_support(monkeypatch):
    # CB (the paper's likelihood) peaks this posterior: exact within the budget
    X, y = _no_roles_problem(60)
    spent = _Spent(monkeypatch)
    fits = [BSIClassifier(roles="all", likelihood="cb", n_jobs=n_jobs).fit(X, y)
            for n_jobs in (1, 2)]
    assert [f.inference_ for f in fits] == ["exact", "exact"]
    assert fits[0].n_hypotheses_ == 3_456_413_271_588_864  # 11 x 11 under Prior 2
    assert fits[0].max_exact_hypotheses is None
    assert np.array_equal(fits[0].posterior_.probabilities, fits[1].posterior_.probabilities)
    forced = BSIClassifier(roles="all", likelihood="cb", inference="exact").fit(X, y)
    assert np.array_equal(forced.posterior_.probabilities, fits[0].posterior_.probabilities)
    assert forced.map_specification_ == fits[0].map_specification_
    # The choice is a function of the counted work only: the same count every time, exact
    # at a budget of exactly that count, sampled one unit below it.
    assert 0 < spent.total / 3 <= auto_budget.AUTO_EXACT_WORK
    work = spent.total / 3
    monkeypatch.setattr(auto_budget, "SAMPLING_TO_EXACT", 0.0)
    monkeypatch.setattr(auto_budget, "AUTO_EXACT_WORK", work)
    assert BSIClassifier(roles="all", likelihood="cb").fit(X, y).inference_ == "exact"
    monkeypatch.setattr(auto_budget, "AUTO_EXACT_WORK", work - 1)
    with _sampled_over_budget():
        assert BSIClassifier(roles="all", n_samples=50,
                             random_state=0).fit(X, y).inference_ == "mcmc"


@contextlib.contextmanager
def _sampled_over_budget(why="needs more than inference='auto''s work budget"):
    """The warnings of a fit sampled because the support is too large for ``auto``.

    The roles warning says why MCMC runs. With the CB likelihood the chains' 50 sweeps on
    these 3.46e15 hypotheses reach the whole posterior (on the 60-mission problem the sampled
    posterior is the exact one, TV 0.0, from 10 sweeps on), and no ``ConvergenceWarning``
    may fire.
    """
    with warnings.catch_warnings():
        warnings.simplefilter("error", ConvergenceWarning)
        with pytest.warns(UserWarning, match=f"With roles='all'.*{why}.*so MCMC samples it"):
            yield


def test_auto_is_exact_on_supports_beyond_int64():
    X = []
    for i in range(20):
        order = np.arange(14) if i % 3 else np.random.default_rng(i).permutation(14)
        tr = np.zeros((15, 14), dtype=np.uint8)
        for t, p in enumerate(order, start=1):
            tr[t:, p] = 1
        X.append(tr)
    y = np.array([int(i % 3 != 0) for i in range(20)])
    clf = BSIClassifier(roles="all", prior="linear_chain", likelihood="cb").fit(X, y)
    assert clf.n_hypotheses_ > 2**64  # 14! x 2**28
    assert clf.inference_ == "exact"
    assert clf.map_specification_.orders == {(a, b) for a in range(14) for b in range(a + 1, 14)}
    assert clf.posterior_.probabilities[0] > 0.99


def test_over_budget_falls_back_to_mcmc_deterministically():
    # A complexity-independent likelihood on these missions is nearly flat: listing what the
    # posterior needs is far over auto's budget, found before the work is done. The chains
    # never visit a state twice (800 samples, 800 states): the posterior is too diffuse to
    # list, and reported by the samples, on whose clause inclusions the chains agree.
    X, y = _no_roles_problem(30)
    with _sampled_over_budget():
        fits = [BSIClassifier(roles="all", likelihood="ci", n_samples=200, random_state=0,
                              n_jobs=n_jobs)
                .fit(X, y) for n_jobs in (1, 2)]
    assert [f.inference_ for f in fits] == ["mcmc", "mcmc"]
    diag = fits[0].mcmc_diagnostics_
    assert diag["sampled"] and diag["n_visited"] == 4 * 200
    assert diag["inclusion_rhat"] <= 1.05
    assert np.array_equal(fits[0].posterior_.probabilities, fits[1].posterior_.probabilities)
    model = make_model(prior="sets_of_chains", likelihood="ci", n_globals=11, n_subtasks=11)
    truth = clause_truth(check_traces(X), resolve_roles(None, None, None, 11, None))
    budget = auto_budget.auto_work_budget(truth, y, model, n_chains=4, n_samples=200,
                                          burn_in=100)
    assert budget > auto_budget.AUTO_EXACT_WORK  # the fallback's cost, not the floor
    messages = set()
    for _ in range(2):
        with pytest.raises(ExactWorkExceeded, match="work budget") as err:
            exact_posterior(truth, y, model, max_work=budget)
        messages.add(str(err.value))
    assert len(messages) == 1


def test_a_cap_on_the_support_still_applies():
    X, y = _no_roles_problem(30)
    with _sampled_over_budget("is above max_exact_hypotheses"):
        assert BSIClassifier(roles="all", max_exact_hypotheses=10**12, n_samples=50,
                             random_state=0).fit(X, y).inference_ == "mcmc"
    with pytest.raises(ValueError, match="max_exact_hypotheses"):
        BSIClassifier(roles="all", inference="exact", max_exact_hypotheses=10**12).fit(X, y)
