"""The grouped engine's early give-up: its lower bound of the listing, against the true one.

``exact._give_up_early`` stops an attempt before the second grouping of the order structures
when a lower bound of the listing's charge (``_listing_bound``) is already over the budget. The
bound must never exceed what the listing really counts and charges, nor the brute-force number
of hypotheses above the keep threshold; and an attempt whose budget suffices must never stop.
"""

import math

import numpy as np
import pytest

from bsi_sklearn.inference import exact
from bsi_sklearn.inference.exact import ExactWorkExceeded, exact_posterior
from bsi_sklearn.model import make_model
from bsi_sklearn.model.priors import PRIORS

SEEDS = range(36)


def _problem(seed):
    # Small problems, mostly flat (a weak likelihood over few demonstrations), where the
    # listing is large and the bound has something to count.
    rng = np.random.default_rng(seed)
    n_g, n = int(rng.integers(0, 3)), int(rng.integers(1, 4))
    prior = PRIORS[seed % len(PRIORS)]
    likelihood = ("cb", "ci")[(seed // 3) % 2]
    epsilon = float(rng.choice([0.05, 0.1, 0.3])) if rng.random() < 0.8 else None
    model = make_model(prior=prior, likelihood=likelihood, n_globals=n_g, n_subtasks=n,
                       epsilon=epsilon)
    n_demos = int(rng.integers(2, 7))
    truth = (rng.random((n_demos, n_g + n + n * n)) < rng.uniform(0.5, 0.95)).astype(np.uint8)
    y = (rng.random(n_demos) < 0.6).astype(np.int64)
    y[0] = 1  # the bound needs an acceptable demonstration (else there is no first grouping)
    tol = float(rng.choice([1e-9, 1e-6, 1e-3]))
    return truth, y, model, tol


def _record(monkeypatch):
    seen = {}

    def give_up_early(first, hs, h_order, subsets, lik, n_pos, log_keep, margin, budget):
        seen["floor"] = exact._listing_floor(first, hs, h_order, subsets, lik, n_pos,
                                             log_keep, margin)

    real_listing = exact._listing

    def listing(found, hs, h_order, subsets, lik, flag, keep, budget):
        before = budget.spent
        out = real_listing(found, hs, h_order, subsets, lik, flag, keep, budget)
        seen["work"], seen["n_list"] = budget.spent - before, out[3]
        return out

    monkeypatch.setattr(exact, "_give_up_early", give_up_early)
    monkeypatch.setattr(exact, "_listing", listing)
    return seen


@pytest.mark.parametrize("seed", SEEDS)
def test_the_bound_never_exceeds_the_listing_nor_brute_force(seed, monkeypatch):
    truth, y, model, tol = _problem(seed)
    seen = _record(monkeypatch)
    res = exact_posterior(truth, y, model, tol=tol)
    brute = exact_posterior(truth, y, model, tol=0.0, grouped=False)
    log_keep = math.log(tol) - math.log(res.n_hypotheses)
    n_above = int((brute.log_prob >= log_keep).sum())  # normalised log posteriors
    if "floor" not in seen:  # no first grouping: nothing satisfies every acceptable demo
        return
    work, n_kept = seen["floor"]
    assert n_kept <= n_above <= seen["n_list"] * (1 + 1e-12)
    assert work <= seen["work"]


def test_the_bound_counts_something_on_flat_problems(monkeypatch):
    # Not vacuous: on most of these problems it counts a good share of the listing.
    shares = []
    for seed in SEEDS:
        truth, y, model, tol = _problem(seed)
        seen = _record(monkeypatch)
        exact_posterior(truth, y, model, tol=tol)
        if "floor" in seen and seen["n_list"] > 0:
            shares.append(seen["floor"][1] / seen["n_list"])
    assert np.mean(np.array(shares) > 0.1) > 0.5


@pytest.mark.parametrize("seed", SEEDS)
def test_an_attempt_within_its_budget_never_gives_up_early(seed):
    # The tightest budget that suffices: the work the enumeration counts without one.
    truth, y, model, tol = _problem(seed)
    free = exact_posterior(truth, y, model, tol=tol)
    tight = exact_posterior(truth, y, model, tol=tol, max_work=free.work)
    np.testing.assert_array_equal(tight.log_prob, free.log_prob)
    np.testing.assert_array_equal(tight.structures, free.structures)
    assert tight.work == free.work


def test_it_gives_up_before_the_second_grouping_when_the_listing_cannot_fit(monkeypatch):
    # A flat posterior whose listing is far over the budget: the bound stops it, and the
    # attempt without the early stop fails too (the decision is the one it would reach).
    truth, y, model, tol = _problem(1)  # a budget of half its work stops it after the tables
    free = exact_posterior(truth, y, model, tol=tol)
    budget = 0.5 * free.work
    with pytest.raises(ExactWorkExceeded, match="a lower bound"):
        exact_posterior(truth, y, model, tol=tol, max_work=budget)
    monkeypatch.setattr(exact, "_give_up_early", lambda *args: None)
    with pytest.raises(ExactWorkExceeded):  # later: the tables, or the listing
        exact_posterior(truth, y, model, tol=tol, max_work=budget)
