"""What the chains found (``_closure``): the visited states' neighbours, once each, in budget."""

import numpy as np
import pytest

from bsi_sklearn.inference import _closure
from bsi_sklearn.inference._closure import CLOSURE_FLOOR, Closure, found_states
from bsi_sklearn.inference._neighbour_weights import weigh_neighbours
from bsi_sklearn.inference.mcmc import deduplicate_demos, score_states, unique_states
from bsi_sklearn.model import make_model
from bsi_sklearn.model.priors import draw_hypothesis
from bsi_sklearn.model.state_layout import join_state


@pytest.fixture
def problem():
    rng = np.random.default_rng(3)
    model = make_model(prior="sets_of_chains", likelihood="ci", n_globals=3, n_subtasks=4,
                       epsilon=0.2)
    truth = (rng.random((30, 3 + 4 + 16)) < 0.85).astype(np.uint8)
    demos = deduplicate_demos(truth, (rng.random(30) < 0.6).astype(np.int64))
    rows, _ = unique_states(np.array([join_state(*draw_hypothesis(model, rng))
                                      for _ in range(8)], dtype=np.int16), np.ones(8))
    return model, demos, rows, score_states(rows.astype(np.int64), demos, model)


def test_the_closure_is_the_visited_states_neighbours_with_their_first_visit(problem):
    model, demos, rows, lp = problem
    first = np.arange(len(rows))[::-1] * 10
    near, near_lp, when = Closure(demos, model).update(rows, lp, first)
    floor = lp.max() - CLOSURE_FLOOR
    assert (near_lp >= floor).all() and len(near)
    for i, row in enumerate(rows):
        own, own_lp = weigh_neighbours(row[None, :], demos, model, floor)
        mine = {r.tobytes(): s for r, s in zip(own, own_lp)}
        got = {r.tobytes(): s for r, s, w in zip(near, near_lp, when) if w == first[i]}
        assert got == mine


def test_each_state_is_weighed_once_and_the_floor_rises(problem, monkeypatch):
    model, demos, rows, lp = problem
    calls = []
    real = _closure.neighbours_within
    monkeypatch.setattr(_closure, "neighbours_within",
                        lambda r, *a: calls.append(len(r)) or real(r, *a))
    closure = Closure(demos, model)
    closure.update(rows[:5], lp[:5], np.zeros(5, dtype=np.int64))
    near, near_lp, _ = closure.update(rows, lp, np.zeros(len(rows), dtype=np.int64))
    assert calls == [5, len(rows) - 5]
    assert (near_lp >= lp.max() - CLOSURE_FLOOR).all()


def test_past_its_budget_the_closure_is_given_up_for_good(problem):
    model, demos, rows, lp = problem
    closure = Closure(demos, model, max_work=1.0)
    assert closure.update(rows, lp, np.zeros(len(rows), dtype=np.int64)) is None
    assert closure.given_up
    assert closure.update(rows[:1], lp[:1], np.zeros(1, dtype=np.int64)) is None


def test_found_states_count_from_the_earlier_of_visit_and_weighing():
    visited = np.array([[0, 1], [1, 1]], dtype=np.int16)
    near = (np.array([[1, 1], [0, 0]], dtype=np.int16), np.array([0.0, np.log(2.0)]),
            np.array([3, 7]))
    probs, when = found_states(visited, np.array([0.0, 0.0]), np.array([5, 9]), near)
    # unique rows sorted: [0, 0], [0, 1], [1, 1]
    np.testing.assert_allclose(probs, [0.5, 0.25, 0.25])
    assert when.tolist() == [7, 5, 3]
