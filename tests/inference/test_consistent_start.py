"""The deterministic optimum's second start: every clause the acceptable demonstrations keep."""

import numpy as np
import pytest

from bsi_sklearn.inference._consistent_start import consistent_start
from bsi_sklearn.inference._local_search import beam_search
from bsi_sklearn.inference.mcmc import deduplicate_demos, deterministic_optimum, score_states
from bsi_sklearn.model import make_model
from bsi_sklearn.model.clauses import clause_index_order, n_clauses
from bsi_sklearn.model.priors import PRIORS, first_structure, log_prior_structure
from bsi_sklearn.model.state_layout import join_state, split_state


def _poset_problem(n, prior, seed, p_edge=0.25, n_g=2, n_demos=60):
    # Acceptable demonstrations keep every global and eventual clause and exactly the orders
    # of a random partial order (a random DAG's transitive closure); the rest are random.
    rng = np.random.default_rng(seed)
    perm = rng.permutation(n)
    before = np.zeros((n, n), dtype=bool)
    for i in range(n):
        for j in range(i + 1, n):
            before[perm[i], perm[j]] = rng.random() < p_edge
    for k in range(n):
        before |= before[:, [k]] & before[[k], :]
    truth = (rng.random((n_demos, n_clauses(n_g, n))) < 0.5).astype(np.uint8)
    y01 = (np.arange(n_demos) % 3 != 0).astype(np.int64)
    for d in np.flatnonzero(y01):
        truth[d, :n_g + n] = 1
        for a in range(n):
            for b in range(n):
                truth[d, clause_index_order(a, b, n_g, n)] = before[a, b] or a == b
    model = make_model(prior=prior, likelihood="cb", n_globals=n_g, n_subtasks=n)
    return deduplicate_demos(truth, y01), model, before


def _ancestor_pairs(parent):
    pairs = set()
    for v in range(len(parent)):
        a = parent[v]
        while a >= 0:
            pairs.add((int(a), v))
            a = parent[a]
    return pairs


@pytest.mark.parametrize("prior", PRIORS)
@pytest.mark.parametrize("seed", range(4))
def test_start_is_in_the_support_and_keeps_only_kept_orders(prior, seed):
    demos, model, before = _poset_problem(12, prior, seed)
    tau, w1, parent = split_state(consistent_start(demos, model), model.n_g, model.n)
    assert tau.all() and w1.all()  # every acceptable demonstration keeps them
    assert np.isfinite(log_prior_structure(parent.astype(np.int64), model))
    if prior != "linear_chain":  # one chain through every subtask keeps what it must
        assert all(before[a, b] for a, b in _ancestor_pairs(parent))


def test_total_order_gives_its_chain():
    # A total order kept by every acceptable demonstration: one chain in that order, under
    # every prior, with every one of its n (n - 1) / 2 orders.
    demos, model, before = _poset_problem(9, "sets_of_chains", 0, p_edge=1.0)
    for prior in PRIORS:
        model = make_model(prior=prior, likelihood="cb", n_globals=2, n_subtasks=9)
        _, _, parent = split_state(consistent_start(demos, model), 2, 9)
        order = {(a, b) for a in range(9) for b in range(9) if before[a, b]}
        assert _ancestor_pairs(parent) == order
        # The optimum: under Prior 1, single blocks from its first chain (index order) do
        # not reach it.
        row, _ = deterministic_optimum(demos, model)
        assert _ancestor_pairs(split_state(row, 2, 9)[2]) == order


def test_without_acceptable_demonstrations_every_clause_is_kept():
    model = make_model(prior="forest", likelihood="cb", n_globals=1, n_subtasks=3)
    demos = deduplicate_demos(np.zeros((4, n_clauses(1, 3)), dtype=np.uint8),
                              np.zeros(4, dtype=np.int64))
    tau, w1, parent = split_state(consistent_start(demos, model), 1, 3)
    assert tau.all() and w1.all()
    assert len(_ancestor_pairs(parent)) == 3  # a chain of three: the deepest forest


@pytest.mark.parametrize("prior", PRIORS)
@pytest.mark.parametrize("n, seed", [(10, 0), (24, 1), (24, 2), (24, 3)])
def test_optimum_at_least_the_beam_from_nothing(prior, n, seed):
    demos, model, _ = _poset_problem(n, prior, seed)
    empty = join_state(np.zeros(model.n_g), np.zeros(n), first_structure(model))
    _, lp_empty = beam_search(empty[None, :], demos, model, 8,
                              4 * n_clauses(model.n_g, n) + 10)
    row, lp = deterministic_optimum(demos, model)
    assert lp == pytest.approx(score_states(row[None, :], demos, model)[0], abs=1e-9)
    assert lp >= lp_empty
    if prior == "sets_of_chains" and n == 24:
        # Single blocks from nothing stop short of the size principle's optimum on a partial
        # order of 24 subtasks: by more than the mode warning.
        assert lp > lp_empty + 27
