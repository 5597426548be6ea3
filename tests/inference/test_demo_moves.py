"""Moves of many clauses about one demonstration: the deterministic optimum past the beam's stop.

Under CB a mislabelled acceptable demonstration that violates many clauses makes a barrier no
single clause crosses: the first gives it up (``|log eps|``, and with many clauses already in,
its share of every clause's ``log 2``) for ``log 2`` per acceptable demonstration, and only
all of them together pay. Where cheaper changes fill the beam, the beam search stops before it.
"""

import numpy as np
import pytest

from bsi_sklearn import BSIClassifier
from bsi_sklearn.inference._demo_moves import best_demo_move, demo_moves
from bsi_sklearn.inference._local_search import beam_search
from bsi_sklearn.inference.mcmc import (
    BEAM_WIDTH,
    deduplicate_demos,
    deterministic_optimum,
    score_states,
)
from bsi_sklearn.model import make_model
from bsi_sklearn.model.clauses import clause_index_eventual, clause_index_order, n_clauses
from bsi_sklearn.model.priors import PRIORS, first_structure, log_prior_structure
from bsi_sklearn.model.state_layout import join_state, split_state


def _barrier(n_good=30, n_barrier=14, n_pos=20):
    # Every acceptable demonstration keeps every G clause but the first, which violates the
    # last n_barrier (as one flipped label would).
    n_g = n_good + n_barrier
    truth = np.ones((n_pos, n_g), dtype=np.uint8)
    truth[0, n_good:] = 0
    model = make_model(prior="sets_of_chains", likelihood="cb", n_globals=n_g, n_subtasks=0)
    return deduplicate_demos(truth, np.ones(n_pos, dtype=np.int64)), model


def test_the_optimum_gives_up_a_demonstration_the_beam_cannot():
    demos, model = _barrier()
    good, every = np.r_[np.ones(30), np.zeros(14)], np.ones(44)
    lp_good, lp_every = score_states(np.array([good, every], dtype=np.int64), demos, model)
    # Giving up the first demonstration for all 14 clauses pays; one clause alone does not.
    assert lp_every > lp_good + 50
    one_more = np.r_[np.ones(31), np.zeros(13)].astype(np.int64)
    assert score_states(one_more[None, :], demos, model)[0] < lp_good - 100
    start = join_state(np.zeros(44), np.zeros(0), first_structure(model))
    beam_row, beam_lp = beam_search(start[None, :], demos, model, BEAM_WIDTH, 4 * 44 + 10)
    assert beam_row.tolist() == good.tolist() and beam_lp == pytest.approx(lp_good)
    row, lp = deterministic_optimum(demos, model)
    assert row.tolist() == every.tolist() and lp == pytest.approx(lp_every)


def test_the_sampler_starts_past_the_barrier():
    X = [np.ones((2, 44), dtype=int) for _ in range(20)]
    X[0][1, 30:] = 0
    roles = dict(global_candidates=list(range(44)), subtasks=[], conditions={})
    clf = BSIClassifier(inference="mcmc", likelihood="cb", random_state=0, **roles).fit(
        X, np.ones(20, int))
    assert clf.map_specification_.globals == frozenset(range(44))
    assert clf.mcmc_diagnostics_["optimum_gap"] == pytest.approx(0.0)


def _random_problem(n_g, n, prior, seed, n_demos=40):
    rng = np.random.default_rng(seed)
    truth = (rng.random((n_demos, n_clauses(n_g, n))) < 0.8).astype(np.uint8)
    y01 = (rng.random(n_demos) < 0.6).astype(np.int64)
    model = make_model(prior=prior, likelihood="cb", n_globals=n_g, n_subtasks=n)
    return deduplicate_demos(truth, y01), model, truth, y01


def _violated(row, truth, n_g, n):
    # Which demonstrations the hypothesis rejects, by brute force over its clauses.
    tau, w1, parent = split_state(np.asarray(row, dtype=np.int64), n_g, n)
    slots = list(np.flatnonzero(tau)) + [clause_index_eventual(w, n_g)
                                         for w in np.flatnonzero(w1)]
    for b in range(n):
        a = parent[b]
        while a >= 0:
            slots.append(clause_index_order(a, b, n_g, n))
            a = parent[a]
    return ~truth[:, slots].astype(bool).all(axis=1) if slots else np.zeros(len(truth), bool)


@pytest.mark.parametrize("prior", PRIORS)
@pytest.mark.parametrize("seed", range(3))
def test_every_move_keeps_or_gives_up_acceptable_demonstrations(prior, seed):
    n_g, n = 4, 5
    demos, model, truth, y01 = _random_problem(n_g, n, prior, seed)
    optimum, _ = deterministic_optimum(demos, model)
    rng = np.random.default_rng(seed)
    rows = [optimum.astype(np.int64)]
    for _ in range(4):  # the optimum's structure, random G and F clauses
        row = rows[0].copy()
        row[:n_g + n] = rng.random(n_g + n) < 0.5
        rows.append(row)
    n_moves = 0
    for row in rows:
        n_moves += _check_moves(row, demos, model, truth, y01)
    assert n_moves


def _check_moves(row, demos, model, truth, y01):
    n_g, n = model.n_g, model.n
    before = _violated(row, truth, n_g, n)
    moves = demo_moves(row, demos, model)
    assert moves.shape[1] == len(row)
    kept_one = given_one = 0
    for move in moves:
        tau, w1, parent = split_state(move, n_g, n)
        # Every move stays in the prior's support.
        assert np.isfinite(log_prior_structure(parent.copy(), model))
        after = _violated(move, truth, n_g, n)
        acceptable = y01 == 1
        if (move <= row).all() or (move[n_g + n:] != row[n_g + n:]).any():
            # A keep move: only drops clauses (cuts orders), so it rejects no more
            # demonstrations, and keeps an acceptable one the row rejected.
            assert not (after & ~before).any()
            assert (before & ~after & acceptable).any()
            kept_one += 1
        else:
            # A give-up move: only adds clauses, each violated by exactly one acceptable
            # demonstration the row kept (the same one for all of them).
            assert (move >= row).all()
            lost = after & ~before & acceptable
            assert len(set(map(bytes, truth[lost]))) == 1
            given_one += 1
    assert kept_one + given_one == len(moves)
    return len(moves)


@pytest.mark.parametrize("prior", PRIORS)
@pytest.mark.parametrize("seed", range(3))
def test_the_optimum_is_never_worse_than_the_beams(prior, seed):
    n_g, n = 3, 5
    demos, model, _, _ = _random_problem(n_g, n, prior, seed)
    start = join_state(np.zeros(n_g), np.zeros(n), first_structure(model))
    _, beam_lp = beam_search(start[None, :], demos, model, 4, 4 * n_clauses(n_g, n) + 10)
    row, lp = deterministic_optimum(demos, model)
    assert lp >= beam_lp
    assert score_states(row.astype(np.int64)[None, :], demos, model)[0] == pytest.approx(lp)
    # And no move of a demonstration improves on it.
    moves = demo_moves(row, demos, model)
    if len(moves):
        assert score_states(moves, demos, model).max() <= lp


def test_keeping_one_case_while_giving_up_another_takes_two_moves():
    # 30 clauses every acceptable case keeps, 14 only the first violates, 15 only the second.
    # From the formula that gave up the first (30 + 14 clauses), keeping it (30) or giving up
    # the second too (59, two cases rejected) is worse; both at once (30 + 15) is better.
    n_g = 30 + 14 + 15
    truth = np.ones((20, n_g), dtype=np.uint8)
    truth[0, 30:44], truth[1, 44:] = 0, 0
    demos = deduplicate_demos(truth, np.ones(20, dtype=np.int64))
    model = make_model(prior="sets_of_chains", likelihood="cb", n_globals=n_g, n_subtasks=0,
                       epsilon=float(np.exp(-180.0)))
    gave_first = np.r_[np.ones(44), np.zeros(15)].astype(np.int64)
    kept_both = np.r_[np.ones(30), np.zeros(29)].astype(np.int64)
    gave_both = np.ones(n_g, dtype=np.int64)
    gave_second = np.r_[np.ones(30), np.zeros(14), np.ones(15)].astype(np.int64)
    lp_first, lp_kept, lp_both, lp_second = score_states(
        np.array([gave_first, kept_both, gave_both, gave_second]), demos, model)
    assert lp_kept < lp_first and lp_both < lp_first < lp_second
    single = score_states(demo_moves(gave_first, demos, model), demos, model)
    assert single.max() < lp_first  # no single move improves
    move, move_lp = best_demo_move(gave_first, lp_first, demos, model, BEAM_WIDTH)
    assert move.tolist() == gave_second.tolist() and move_lp == pytest.approx(lp_second)
