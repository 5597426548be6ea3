"""What a chain reached: its visited states and their one-block neighbours (``_reach``).

The reference is the move set itself: the one-block neighbours that the local search
enumerates (``_local_search.neighbourhood``, the Gibbs blocks' candidates, every one scored
from scratch), compared pair by pair, for every prior.
"""

import numpy as np
import pytest

from bsi_sklearn.inference._local_search import neighbourhood
from bsi_sklearn.inference._reach import reach
from bsi_sklearn.inference.mcmc import deduplicate_demos, unique_states
from bsi_sklearn.model import make_model
from bsi_sklearn.model.priors import PRIORS, draw_hypothesis
from bsi_sklearn.model.state_layout import join_state


def _problem(prior, n_g, n, seed):
    rng = np.random.default_rng(seed)
    model = make_model(prior=prior, likelihood="ci", n_globals=n_g, n_subtasks=n, epsilon=0.1)
    truth = (rng.random((12, n_g + n + n * n)) < 0.8).astype(np.uint8)
    demos = deduplicate_demos(truth, (rng.random(12) < 0.5).astype(np.int64))
    return model, demos, rng


def _neighbours(row, demos, model):
    rows, _ = neighbourhood(row[None, :].astype(np.int64), demos, model, -np.inf)
    return {r.tobytes() for r in rows.astype(np.int64)} - {row.astype(np.int64).tobytes()}


@pytest.mark.parametrize("prior", PRIORS)
@pytest.mark.parametrize("seed", range(6))
def test_reach_is_the_move_sets_neighbourhood(prior, seed):
    n_g, n = 3, 4
    model, demos, rng = _problem(prior, n_g, n, seed)
    draws = [join_state(*draw_hypothesis(model, rng)) for _ in range(6)]
    # The union: the draws, all their one-block neighbours, and the neighbours of a few of
    # those (two blocks from a draw), each once.
    rows = list(draws)
    for d in draws:
        near = [np.frombuffer(b, dtype=np.int64) for b in sorted(_neighbours(d, demos, model))]
        rows += near + [x for m in near[:3] for x in
                        (np.frombuffer(b, dtype=np.int64)
                         for b in sorted(_neighbours(m, demos, model)))]
    union, _ = unique_states(np.array(rows, dtype=np.int64), np.ones(len(rows), np.int64))
    key = [r.tobytes() for r in union]
    adjacent = [_neighbours(r, demos, model) for r in union]
    # Two chains: one visited the first draw, the other every third state.
    chains = [np.array([key.index(draws[0].tobytes())]), np.arange(0, len(union), 3)]
    got = reach(union, model, chains)
    for k, visits in enumerate(chains):
        want = set(visits.tolist())
        for i in visits:
            want |= {j for j in range(len(union)) if key[j] in adjacent[i]}
        assert got[k].tolist() == sorted(want)


def test_reach_of_one_state_and_of_none():
    model = make_model(prior="sets_of_chains", likelihood="cb", n_globals=1, n_subtasks=2)
    row = np.array([[1, 0, 1, -1, 0]])
    got = reach(row, model, [np.array([0]), np.array([], dtype=np.int64)])
    assert [g.tolist() for g in got] == [[0], []]
