"""One-block neighbourhoods weighed incrementally (``_neighbour_weights``) against scoring.

The reference is ``_local_search.neighbourhood``: the same move set, every neighbour scored
from scratch. Compared row by row and score by score, for every prior and likelihood, with
floors that keep everything, some and nothing.
"""

import numpy as np
import pytest

from bsi_sklearn.inference._local_search import neighbourhood
from bsi_sklearn.inference._neighbour_weights import (
    neighbour_work,
    neighbours_within,
    weigh_neighbours,
)
from bsi_sklearn.inference.mcmc import deduplicate_demos, score_states
from bsi_sklearn.model import make_model
from bsi_sklearn.model.likelihood import LIKELIHOODS
from bsi_sklearn.model.priors import PRIORS, draw_hypothesis
from bsi_sklearn.model.state_layout import join_state


def _problem(prior, likelihood, n_g, n, seed, flip_prior=None):
    rng = np.random.default_rng(seed)
    n_demos = 40
    model = make_model(prior=prior, likelihood=likelihood, n_globals=n_g, n_subtasks=n,
                       epsilon=None if flip_prior else 0.1, flip_prior=flip_prior,
                       n_demos=n_demos)
    truth = (rng.random((n_demos, n_g + n + n * n)) < 0.85).astype(np.uint8)
    demos = deduplicate_demos(truth, (rng.random(n_demos) < 0.6).astype(np.int64))
    rows = np.array([join_state(*draw_hypothesis(model, rng)) for _ in range(5)],
                    dtype=np.int64)
    return model, demos, rows


def _as_dict(rows, scores, drop=()):
    # Rows to scores, those the prior rules out (-inf) left out: the move set enumerates
    # places the prior forbids, the Gibbs moves do not weigh them.
    out = {}
    for r, s in zip(rows.astype(np.int64), scores):
        key = r.tobytes()
        if key not in drop and s > -np.inf:
            assert out.setdefault(key, s) == s  # a row found twice has one score
    return out


@pytest.mark.parametrize("prior", PRIORS)
@pytest.mark.parametrize("likelihood", LIKELIHOODS)
@pytest.mark.parametrize("seed", range(3))
def test_weighed_neighbours_are_the_scored_ones(prior, likelihood, seed):
    model, demos, rows = _problem(prior, likelihood, 3, 4, seed)
    sources = {r.tobytes() for r in rows}
    ref_rows, ref_lp = neighbourhood(rows, demos, model, -np.inf)
    want = _as_dict(ref_rows, ref_lp, drop=sources)
    finite = np.array(sorted(want.values()))
    assert len(finite) > 10
    for floor in (-np.inf, float(np.median(finite)), float(finite[-1]),
                  float(finite[-1]) + 1.0):
        got_rows, got_lp = weigh_neighbours(rows, demos, model, floor)
        got = _as_dict(got_rows, got_lp, drop=sources)
        assert got == {k: v for k, v in want.items() if v >= floor}
        np.testing.assert_array_equal(got_lp, score_states(got_rows.astype(np.int64), demos,
                                                           model))
    for row in rows:  # a hypothesis is not its own neighbour
        own, _ = weigh_neighbours(row[None, :], demos, model, -np.inf)
        assert row.tobytes() not in {r.tobytes() for r in own.astype(np.int64)}


@pytest.mark.parametrize("prior", PRIORS)
def test_weighed_neighbours_with_a_flip_prior_and_with_one_subtask(prior):
    for n, flip_prior, likelihood in ((4, (1.0, 9.0), "ci"), (4, (1.0, 9.0), "calibrated"),
                                      (1, None, "ci"), (0, None, "ci")):
        model, demos, rows = _problem(prior, likelihood, 3, n, 7, flip_prior)
        ref_rows, ref_lp = neighbourhood(rows, demos, model, -np.inf)
        sources = {r.tobytes() for r in rows}
        want = _as_dict(ref_rows, ref_lp, drop=sources)
        got_rows, got_lp = weigh_neighbours(rows, demos, model, -np.inf)
        assert _as_dict(got_rows, got_lp, drop=sources) == want and want


def test_no_rows_no_neighbours():
    model, demos, rows = _problem("sets_of_chains", "cb", 2, 2, 0)
    got_rows, got_lp = weigh_neighbours(rows[:0], demos, model, -np.inf)
    assert got_rows.shape == (0, rows.shape[1]) and got_lp.shape == (0,)


def test_neighbours_within_a_budget_say_whose_they_are_and_stop_after_a_row():
    model, demos, rows = _problem("sets_of_chains", "cb", 3, 4, 1)
    whole = weigh_neighbours(rows, demos, model, -np.inf)
    found, scores, sources, done, spent = neighbours_within(rows, demos, model, -np.inf)
    assert done == len(rows) and np.array_equal(found, whole[0])
    per_row, per_kept = neighbour_work(demos, model)
    assert spent >= len(rows) * per_row + len(found) * per_kept
    for i, row in enumerate(rows):
        own = weigh_neighbours(row[None, :], demos, model, -np.inf)[0]
        assert np.array_equal(found[sources == i], own)
    # the work is counted after every row: a budget below one row's still does one
    part = neighbours_within(rows, demos, model, -np.inf, max_work=per_row / 2)
    assert part[3] == 1 and np.array_equal(part[0], found[sources == 0])
    assert neighbours_within(rows, demos, model, -np.inf, max_work=0.0)[3] == 1
