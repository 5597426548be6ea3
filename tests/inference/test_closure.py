"""What the chains found (``_closure``): through the most probable states, once each, in budget.

The reference is a fixed-point iteration over ``weigh_neighbours`` (itself tested against
the local search's from-scratch scores) and, from the ties of the best, ``exchange_neighbours``
(tested against exchanging by hand and ``score_states``).
"""

import numpy as np
import pytest

from bsi_sklearn.inference import _closure, _local_search
from bsi_sklearn.inference._closure import (
    CLOSURE_EXPAND,
    CLOSURE_FLOOR,
    EXCHANGE_LEVEL,
    Closure,
    found_states,
)
from bsi_sklearn.inference._exchanges import ExchangeWeigher, exchange_neighbours
from bsi_sklearn.inference._local_search import COMPLETE_FLOOR, complete_support
from bsi_sklearn.inference._neighbour_weights import weigh_neighbours
from bsi_sklearn.inference.mcmc import deduplicate_demos, score_states, unique_states
from bsi_sklearn.model import make_model
from bsi_sklearn.model.priors import draw_hypothesis
from bsi_sklearn.model.state_layout import join_state


def _random_problem(prior, seed):
    # CI on 30 random demonstrations (3 globals, 4 subtasks) and 8 states drawn from the prior.
    rng = np.random.default_rng(seed)
    model = make_model(prior=prior, likelihood="ci", n_globals=3, n_subtasks=4, epsilon=0.2)
    truth = (rng.random((30, 3 + 4 + 16)) < 0.85).astype(np.uint8)
    demos = deduplicate_demos(truth, (rng.random(30) < 0.6).astype(np.int64))
    rows, _ = unique_states(np.array([join_state(*draw_hypothesis(model, rng))
                                      for _ in range(8)], dtype=np.int16), np.ones(8))
    return model, demos, rows, score_states(rows.astype(np.int64), demos, model)


@pytest.fixture
def problem():
    return _random_problem("sets_of_chains", 3)


def _reference(rows, lp, first, demos, model):
    # The closure by fixed-point iteration: weigh the visited states and every found state
    # within CLOSURE_EXPAND of the best visited one (and the exchanges of its ties), until no
    # state's time (the least first visit of a weighed state it is reached from) changes.
    neighbours = {}
    score = {r.tobytes(): float(s) for r, s in zip(rows, lp)}
    tied = float(lp.max()) - EXCHANGE_LEVEL

    def near(row):
        key = row.tobytes()
        if key not in neighbours:
            got = weigh_neighbours(row[None, :], demos, model, -np.inf)
            neighbours[key] = list(zip(got[0], got[1]))
            if score[key] >= tied:
                neighbours[key] += list(zip(*exchange_neighbours(row, demos, model, -np.inf)))
        return neighbours[key]

    when = {r.tobytes(): int(f) for r, f in zip(rows, first)}
    found, weighed = {}, {r.tobytes(): r for r in rows}
    floor, expand = float(lp.max()) - CLOSURE_FLOOR, float(lp.max()) - CLOSURE_EXPAND
    while True:
        changed = False
        for key, row in list(weighed.items()):
            for nrow, s in near(row):
                score.setdefault(nrow.tobytes(), float(s))
                if s < floor:
                    continue
                k = nrow.tobytes()
                if when[key] < when.get(k, np.iinfo(np.int64).max):
                    when[k] = when[key]
                    changed = True
                found[k] = (nrow, s)
                if s >= expand and k not in weighed:
                    weighed[k] = nrow
                    changed = True
        if not changed:
            return {k: (s, when[k]) for k, (_, s) in found.items() if s >= floor}


def test_the_closure_is_found_through_the_most_probable_states_with_first_times(problem):
    model, demos, rows, lp = problem
    first = np.arange(len(rows))[::-1] * 10
    near, near_lp, when = Closure(demos, model).update(rows, lp, first)
    got = {r.tobytes(): (s, w) for r, s, w in zip(near, near_lp, when)}
    assert got == _reference(rows, lp, first, demos, model)
    for row in rows:  # every visited state's neighbours above the floor are found
        own = weigh_neighbours(row[None, :], demos, model, lp.max() - CLOSURE_FLOOR)[0]
        assert {r.tobytes() for r in own} <= set(got) | {r.tobytes() for r in rows}
    assert (near_lp >= lp.max() - CLOSURE_FLOOR).all()
    # a lone visited state of a flat problem already reaches far beyond its neighbours
    one = Closure(demos, model).update(rows[:1], lp[:1], first[:1])
    assert len(one[0]) > len(weigh_neighbours(rows[:1], demos, model, -np.inf)[0])


def _plateau():
    # Every acceptable demonstration keeps 4 < 0, and 4 < b and 0 < b for b = 1, 2, 3, and
    # nothing else: under chains, 4 -> 0 -> 1, 4 -> 0 -> 2 and 4 -> 0 -> 3 are equally
    # probable. From one to another is two blocks (take b out, put c in: moving 0 instead
    # loses 4 -> 0) across a valley of two orders (2 x 60 log 2 nats, below the floor). One
    # exchange joins them.
    n_g, n = 1, 5
    truth = np.zeros((80, n_g + n + n * n), dtype=np.uint8)
    y01 = (np.arange(80) < 60).astype(np.int64)
    truth[:60, :n_g + n] = 1
    for a, b in [(4, 0), (4, 1), (4, 2), (4, 3), (0, 1), (0, 2), (0, 3)]:
        truth[:60, n_g + n + a * n + b] = 1
    for a in range(n):
        truth[:, n_g + n + a * n + a] = 1
    model = make_model(prior="sets_of_chains", likelihood="cb", n_globals=n_g, n_subtasks=n)
    demos = deduplicate_demos(truth, y01)
    plateau = []
    for b in (1, 2, 3):
        parent = [-1] * n
        parent[0], parent[b] = 4, 0
        plateau.append(join_state([1], [1] * n, parent, dtype=np.int16))
    lp = score_states(np.array(plateau, dtype=np.int64), demos, model)
    return model, demos, plateau, lp


def test_a_plateau_two_blocks_apart_is_found_whole_through_exchanges(monkeypatch):
    model, demos, plateau, lp = _plateau()
    assert lp[0] == lp[1] == lp[2]
    first = np.zeros(1, dtype=np.int64)
    rows, found_lp, when = Closure(demos, model).update(plateau[0][None, :], lp[:1], first)
    got = {r.tobytes(): s for r, s in zip(rows, found_lp)}
    assert all(got[r.tobytes()] == lp[0] for r in plateau)  # exact, as score_states
    assert when.max() == 0
    # without the exchanges, one block at a time, the other two are out of reach
    monkeypatch.setattr(ExchangeWeigher, "within",
                        lambda self, row, floor: (np.empty((0, row.shape[0]), np.int16),
                                                  np.empty(0), 0.0))
    rows, _, _ = Closure(demos, model).update(plateau[0][None, :], lp[:1], first)
    assert {r.tobytes() for r in plateau[1:]} & {r.tobytes() for r in rows} == set()


def test_ties_are_weighed_beyond_the_closure_budget_within_their_own():
    # Work on the ties of the best is charged to their own budget first (a share of the
    # sampling the chains may still do): with no other budget the plateau is still found
    # whole, and without that share the closure gives up.
    model, demos, plateau, lp = _plateau()
    first = np.zeros(1, dtype=np.int64)
    closure = Closure(demos, model, max_work=0.0, sampling_work=1e12)
    rows, _, _ = closure.update(plateau[0][None, :], lp[:1], first)
    assert {r.tobytes() for r in plateau} <= {r.tobytes() for r in rows}
    assert 0 < closure.tied_left < _closure.PLATEAU_SHARE * 1e12
    assert Closure(demos, model, max_work=0.0).update(plateau[0][None, :], lp[:1],
                                                      first) is None


def test_each_state_is_weighed_once(problem, monkeypatch):
    model, demos, rows, lp = problem
    calls = []
    real = _closure.NeighbourWeigher.one
    monkeypatch.setattr(_closure.NeighbourWeigher, "one",
                        lambda self, r, *a: calls.append(r.tobytes()) or real(self, r, *a))
    closure = Closure(demos, model)
    closure.update(rows[:5], lp[:5], np.zeros(5, dtype=np.int64))
    n_first = len(calls)
    assert n_first == len(set(calls)) > 5
    closure.update(rows, lp, np.zeros(len(rows), dtype=np.int64))
    assert len(calls) == len(set(calls))


def test_past_its_memory_the_closure_is_given_up(problem, monkeypatch):
    model, demos, rows, lp = problem
    first = np.zeros(len(rows), dtype=np.int64)
    near = Closure(demos, model).update(rows, lp, first)
    kept = len(near[0]) * (4 * rows.shape[1] + 64)  # at least: every found row, once
    monkeypatch.setattr(_closure, "CLOSURE_BYTES", kept // 2)
    closure = Closure(demos, model)
    assert closure.update(rows, lp, first) is None and closure.given_up
    assert not closure._near  # what it held is let go


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
    probs, when, keys = found_states(visited, np.array([0.0, 0.0]), np.array([5, 9]), near)
    assert keys == [r.tobytes() for r in (visited[0], visited[1], near[0][1])]
    # the states in the order first seen: [0, 1], [1, 1], [0, 0]
    np.testing.assert_allclose(probs, [0.25, 0.25, 0.5])
    assert when.tolist() == [5, 3, 7]


def test_a_chain_reaches_what_its_own_states_lead_to(problem):
    from bsi_sklearn.inference._closure import found_by_chain

    model, demos, rows, lp = problem
    first = np.zeros(len(rows), dtype=np.int64)
    closure = Closure(demos, model)
    near = closure.update(rows, lp, first)
    probs, when, keys = found_states(rows, lp, first, near)
    whole, part, alone = found_by_chain(closure, rows, [np.arange(len(rows)), np.arange(3),
                                                        np.array([2, 2])], keys)
    # all the visited states lead to everything found; a chain's share is in it
    assert whole.tolist() == list(range(len(keys)))
    assert set(part.tolist()) <= set(whole.tolist()) and set(alone) <= set(part)
    # ... and holds its own states and their neighbours above the floor
    floor = lp.max() - CLOSURE_FLOOR
    own = {rows[2].tobytes()} | {r.tobytes() for r in
                                  weigh_neighbours(rows[2:3], demos, model, floor)[0]}
    assert own <= {keys[i] for i in alone}


def _reach_by_hand(closure, keys):
    # What the states `keys` lead to, as the last update found, over the closure's lists: the
    # states themselves, and those above the floor one block from them or from a state so
    # found within CLOSURE_EXPAND of the best.
    floor, expand = closure._levels
    out, todo = set(keys), list(keys)
    while todo:
        lps, near = closure._near[todo.pop()]
        for lp, k in zip(lps, near):
            if lp >= floor and k not in out:
                out.add(k)
                if lp >= expand:
                    todo.append(k)
    return out


def test_the_compiled_traversal_is_the_closures_reach(problem):
    # found_by_chain walks numbered states in compiled code: the same sets as a traversal of
    # the closure's lists by hand
    from bsi_sklearn.inference._closure import found_by_chain

    model, demos, rows, lp = problem
    rng = np.random.default_rng(0)
    first = rng.integers(0, 50, size=len(rows))
    closure = Closure(demos, model)
    near = closure.update(rows, lp, first)
    _, _, keys = found_states(rows, lp, first, near)
    chains = [rng.choice(len(rows), size=k) for k in (1, 2, 5, len(rows))]
    for chain, got in zip(chains, found_by_chain(closure, rows, chains, keys)):
        expected = _reach_by_hand(closure, {rows[i].tobytes() for i in chain})
        assert [keys[i] for i in got] == sorted(expected, key=keys.index)


def test_a_plateau_too_large_for_the_budget_is_given_up_at_once():
    # With room for about one tie's work, the first tie's exchanges find two more ties: at
    # the first tie's cost they would pass what is left, so the closure gives up then,
    # without spending the rest.
    model, demos, plateau, lp = _plateau()
    first = np.zeros(1, dtype=np.int64)
    probe = Closure(demos, model, max_work=0.0, sampling_work=1e12)
    probe.update(plateau[0][None, :], lp[:1], first)
    whole = _closure.PLATEAU_SHARE * 1e12 - probe.tied_left  # the three ties' work
    per_tie = probe._tie_cost[0]
    assert whole >= 3 * per_tie
    closure = Closure(demos, model, max_work=0.0,
                      sampling_work=1.5 * per_tie / _closure.PLATEAU_SHARE)
    assert closure.update(plateau[0][None, :], lp[:1], first) is None
    assert closure.given_up
    spent = 1.5 * per_tie - closure.tied_left - closure.left
    assert spent < 2 * per_tie < whole  # one tie weighed, not three


@pytest.mark.parametrize("prior", ["sets_of_chains", "forest"])
def test_complete_support_skips_what_the_closure_holds_whole(prior):
    # The states the last update traversed have every neighbour above its floor among the
    # states it found: completing the support without weighing them again (complete=) gives
    # the same support and scores as weighing every source, and weighs fewer sources.
    model, demos, rows, lp = _random_problem(prior, 5)
    rows, lp = rows[np.isfinite(lp)], lp[np.isfinite(lp)]
    closure = Closure(demos, model)
    near = closure.update(rows, lp, np.zeros(len(rows), dtype=np.int64))
    support = np.concatenate([rows, near[0]])
    support_lp = np.concatenate([lp, near[1]])
    floor = float(support_lp.max()) - COMPLETE_FLOOR
    assert len(closure.complete(floor)) >= len(rows)  # the visited states at least
    # below the update's own floor (its best before it ran, less CLOSURE_FLOOR) nothing is
    # known whole
    below = float(lp.max()) - CLOSURE_FLOOR - 1e-6
    assert closure.complete(below) == frozenset()
    sources = []
    real = _local_search.neighbourhood

    def counted(src, *a):
        sources.append(len(src))
        return real(src, *a)

    def completed(complete):
        extra, extra_lp = complete_support(support, support_lp, demos, model, complete)
        return {r.tobytes(): s for r, s in zip(np.concatenate([support, extra]),
                                               np.concatenate([support_lp, extra_lp]))}

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(_local_search, "neighbourhood", counted)
        every, skipped = completed(None), completed(closure.complete)
    assert every == skipped
    assert sources[1] < sources[0]
