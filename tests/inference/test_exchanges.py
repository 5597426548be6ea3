"""Exchange neighbours (two subtasks trade places) against exchanging and scoring by hand."""

import numpy as np
import pytest

from bsi_sklearn.inference._exchanges import exchange_neighbours, n_exchanges
from bsi_sklearn.inference.mcmc import deduplicate_demos, score_states
from bsi_sklearn.model import make_model
from bsi_sklearn.model.likelihood import LIKELIHOODS
from bsi_sklearn.model.priors import PRIORS, draw_hypothesis
from bsi_sklearn.model.state_layout import join_state, split_state


def _exchanged(row, n_g, n, x, y):
    # By hand: the structure relabelled by the transposition (x y).
    tau, w1, parent = split_state(np.asarray(row, dtype=np.int64), n_g, n)
    swap = {x: y, y: x}
    new = np.empty(n, dtype=np.int64)
    for v in range(n):
        p = int(parent[v])
        new[swap.get(v, v)] = swap.get(p, p)
    return join_state(tau, w1, new)


@pytest.mark.parametrize("prior", PRIORS)
@pytest.mark.parametrize("likelihood", LIKELIHOODS)
@pytest.mark.parametrize("n", [1, 2, 5])
def test_exchange_neighbours_are_the_exchanges_above_the_floor(prior, likelihood, n):
    rng = np.random.default_rng(n)
    n_g = 2
    model = make_model(prior=prior, likelihood=likelihood, n_globals=n_g, n_subtasks=n,
                       **({"flip_prior": (1, 9), "n_demos": 80} if likelihood == "ci" else {}))
    truth = (rng.random((80, n_g + n + n * n)) < 0.85).astype(np.uint8)
    demos = deduplicate_demos(truth, (rng.random(80) < 0.6).astype(np.int64))
    for _ in range(6):
        row = join_state(*draw_hypothesis(model, rng))
        lp_row = score_states(row[None, :], demos, model)[0]
        want = {}
        for x in range(n):
            for y in range(x + 1, n):
                other = _exchanged(row, n_g, n, x, y)
                if not np.array_equal(other, row):
                    want[other.tobytes()] = score_states(other[None, :], demos, model)[0]
        assert len(want) <= n_exchanges(n)
        for floor in (-np.inf, lp_row - 3.0):
            got, lps = exchange_neighbours(row, demos, model, floor)
            got_d = {r.astype(np.int64).tobytes(): lp for r, lp in zip(got, lps)}
            assert len(got_d) == len(got)
            assert got_d.keys() == {k for k, v in want.items() if v >= floor}
            for k, lp in got_d.items():
                assert lp == want[k]  # scored from scratch: equal, not close
