"""inference="auto"'s exact budget: at least the floor, else what its MCMC fallback costs."""

import numpy as np
import pytest

import bsi_sklearn.inference.auto_budget as auto_budget
from bsi_sklearn import BSIClassifier
from bsi_sklearn.data.roles import resolve_roles
from bsi_sklearn.data.traces import check_traces
from bsi_sklearn.inference.exact import ExactWorkExceeded, exact_posterior
from bsi_sklearn.inference.mcmc import deduplicate_demos, sampling_count, temperature_ladder
from bsi_sklearn.model import make_model
from bsi_sklearn.model.clauses import clause_truth


def _problem():
    rng = np.random.default_rng(3)
    X = []
    for _ in range(24):
        tr = np.zeros((6, 5), dtype=np.uint8)
        for p in rng.permutation(4)[:3]:
            tr[int(rng.integers(1, 6)):, p] = 1
        tr[:, 4] = rng.random() < 0.9
        X.append(tr)
    y = np.array([int(x[-1, :3].all() and x[:, 4].all()) for x in X])
    y[:2] = 1 - y[:2]  # two wrong labels: a posterior that is not trivially peaked
    roles = resolve_roles([4], [0, 1, 2, 3], None, 5, None)
    model = make_model(prior="sets_of_chains", likelihood="cb", n_globals=1, n_subtasks=4)
    return X, y, clause_truth(check_traces(X), roles), model


def test_sampling_count_is_chains_sweeps_rungs_moves_and_rows():
    X, y, truth, model = _problem()
    demos = deduplicate_demos(truth, y)
    rungs = len(temperature_ladder(demos, model))
    rows = demos.truth_t.shape[1]
    count = sampling_count(truth, y, model, n_chains=4, n_samples=1000, burn_in=100)
    assert count == 4 * 1100 * rungs * (1 + 4 + 4 * 5) * rows
    assert sampling_count(truth, y, model, n_chains=2, n_samples=1000, burn_in=100,
                          n_temperatures=1) == count / 2 / rungs
    # duplicated demonstrations are one row to the sampler
    assert sampling_count(np.vstack([truth, truth]), np.concatenate([y, y]), model,
                          n_chains=4, n_samples=1000, burn_in=100) == \
        sampling_count(truth, y, model, n_chains=4, n_samples=1000, burn_in=100)


def test_the_budget_is_the_floor_or_the_fallback_cost():
    X, y, truth, model = _problem()
    count = sampling_count(truth, y, model, n_chains=4, n_samples=10_000, burn_in=100)
    budget = auto_budget.auto_work_budget(truth, y, model, n_chains=4, n_samples=10_000,
                                          burn_in=100)
    assert budget == max(auto_budget.AUTO_EXACT_WORK, auto_budget.SAMPLING_TO_EXACT * count)
    small = auto_budget.auto_work_budget(truth, y, model, n_chains=1, n_samples=1, burn_in=0)
    assert small == auto_budget.AUTO_EXACT_WORK


def test_exact_work_is_the_budget_it_needs():
    # ExactResult.work is what the enumeration charged: a budget of exactly that passes, one
    # unit less stops it (also when the walk down the tables is what does not fit).
    X, y, truth, model = _problem()
    res = exact_posterior(truth, y, model)
    assert res.work > 0
    again = exact_posterior(truth, y, model, max_work=res.work)
    assert np.array_equal(again.log_prob, res.log_prob) and again.work == res.work
    with pytest.raises(ExactWorkExceeded, match="work budget"):
        exact_posterior(truth, y, model, max_work=res.work - 1)
    assert exact_posterior(truth, y, model, grouped=False).work is None


def test_auto_is_exact_up_to_the_fallback_cost(monkeypatch):
    # With the floor out of the way, auto enumerates exactly while the enumeration costs no
    # more than the sampling would (in exact units), and samples one unit beyond.
    X, y, truth, model = _problem()
    work = exact_posterior(truth, y, model).work
    params = dict(global_candidates=[4], subtasks=[0, 1, 2, 3], conditions={}, n_samples=200,
                  likelihood="cb", random_state=0)  # the model above
    count = sampling_count(truth, y, model, n_chains=4, n_samples=200, burn_in=100)
    monkeypatch.setattr(auto_budget, "AUTO_EXACT_WORK", 0.0)
    monkeypatch.setattr(auto_budget, "SAMPLING_TO_EXACT", work / count)
    fit = BSIClassifier(**params).fit(X, y)
    assert fit.inference_ == "exact"
    forced = BSIClassifier(**params, inference="exact").fit(X, y)
    assert np.array_equal(fit.posterior_.probabilities, forced.posterior_.probabilities)
    monkeypatch.setattr(auto_budget, "SAMPLING_TO_EXACT", work / count * 0.999)
    assert BSIClassifier(**params).fit(X, y).inference_ == "mcmc"
