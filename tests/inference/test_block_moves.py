"""One-block moves scored from the row's counts (as the beam search does), against _score."""

import numpy as np
import pytest
from numba import njit

from bsi_sklearn.inference._block_moves import (
    N_MOVE,
    flip_scratch,
    move_scratch,
    n_flip_bits,
    n_neighbours_max,
    neighbours,
    prepare_flips,
    prepare_moves,
    score_flip,
    score_moved,
)
from bsi_sklearn.inference._chain_kernel import fill_viol
from bsi_sklearn.inference._local_search import _load, _score, _scratch
from bsi_sklearn.inference.mcmc import deduplicate_demos
from bsi_sklearn.model import make_model
from bsi_sklearn.model.likelihood import LIKELIHOODS
from bsi_sklearn.model.priors import PRIORS, draw_hypothesis, log_prior_globals
from bsi_sklearn.model.state_layout import join_state, split_state


def _problem(prior, likelihood, n, seed, n_g=6, **priors):
    # Six global slots, three of them pattern clauses; 300 demonstrations, some repeated.
    rng = np.random.default_rng(seed)
    model = make_model(prior=prior, likelihood=likelihood, n_globals=n_g, n_subtasks=n,
                       p_patterns=[0.1, 0.3, 0.05], **priors)
    truth = (rng.random((300, n_g + n + n * n)) < 0.9).astype(np.uint8)
    demos = deduplicate_demos(truth, (rng.random(300) < 0.6).astype(np.int64))
    rows = np.array([join_state(*draw_hypothesis(model, rng)) for _ in range(6)],
                    dtype=np.int64)
    pool = np.empty((n_neighbours_max(n_g, n), rows.shape[1]), dtype=np.int64)
    return model, demos, rows, pool


def _move_buffer(model):
    return np.empty((n_neighbours_max(model.n_g, model.n), N_MOVE), dtype=np.int64)


@njit
def _flip_scores(rows, demos, model, scratch, other, work, pool, moves, viol, flips):
    # Per row, every bit flip scored both ways: (from the row's counts and the row loaded in
    # `scratch`, from scratch on the flipped row written out by neighbours).
    n_bits = n_flip_bits(model)
    out = np.empty((rows.shape[0], n_bits, 2))
    kept = True  # the loaded row is left as it was
    for i in range(rows.shape[0]):
        neighbours(rows[i], model, pool, 0, work, moves)
        tau, w1, parent = split_state(rows[i], model.n_g, model.n)
        n_conj = fill_viol(viol, tau.copy(), w1.copy(), parent.copy(), demos.truth_t, model)
        _load(rows[i], model, scratch)
        prepare_flips(viol, model, scratch, flips)
        for j in range(n_bits):
            out[i, j, 0] = score_flip(j, n_conj, demos, model, scratch, flips)
            out[i, j, 1] = _score(pool[j], demos, model, other)
        for j in range(model.n_g):
            kept = kept and scratch.tau[j] == tau[j]
        for w in range(model.n):
            kept = kept and scratch.w1[w] == w1[w] and scratch.parent[w] == parent[w]
    return out, kept


@pytest.mark.parametrize("prior", PRIORS)
@pytest.mark.parametrize("likelihood", LIKELIHOODS)
@pytest.mark.parametrize("n", [0, 1, 4])
def test_flip_scores_are_the_scores_bit_for_bit(prior, likelihood, n):
    model, demos, rows, pool = _problem(prior, likelihood, n, n)
    got, kept = _flip_scores(rows, demos, model, _scratch(demos, model), _scratch(demos, model),
                             np.empty((3, n), dtype=np.int64), pool, _move_buffer(model),
                             np.zeros(demos.truth_t.shape[1], dtype=np.int32),
                             flip_scratch(demos, model))
    finite = np.isfinite(got[..., 1])
    assert finite.sum() > 10
    np.testing.assert_array_equal(got[..., 0], got[..., 1])  # equal, not close
    assert kept


@njit
def _move_scores(rows, demos, model, scratch, work, pool, moves, buf, viol):
    # Per row, every structure move scored both ways: (from the row's counts less the moved
    # subtask's clauses, as bitsets; from scratch on the row neighbours writes out).
    n_bits = n_flip_bits(model)
    out = np.empty((rows.shape[0], pool.shape[0], 2))
    out[:] = np.nan
    for i in range(rows.shape[0]):
        k = neighbours(rows[i], model, pool, 0, work, moves)
        tau, w1, parent = split_state(rows[i], model.n_g, model.n)
        n_conj = fill_viol(viol, tau.copy(), w1.copy(), parent.copy(), demos.truth_t, model)
        lp_g = log_prior_globals(tau, model)
        v = -1
        rest = (np.int64(0), 0.0, 0.0, 0.0, 0.0)
        for j in range(n_bits, k):
            if moves[j, 1] != v:
                v = moves[j, 1]
                rest = prepare_moves(rows[i], v, viol, n_conj, demos, model, buf)
            out[i, j, 0] = score_moved(rows[i], moves[j], lp_g, rest, demos, model, scratch,
                                       buf)
            out[i, j, 1] = _score(pool[j], demos, model, scratch)
    return out


@pytest.mark.parametrize("prior", PRIORS)
@pytest.mark.parametrize("likelihood", LIKELIHOODS)
@pytest.mark.parametrize("n, priors", [
    (4, {}), (9, {}), (9, {"p_eventual": "learned", "p_part": "learned"})])
def test_structure_move_scores_are_the_scores_bit_for_bit(prior, likelihood, n, priors):
    # n = 9 with the chain cuts learned: long chains, whose moves (chains scored from the
    # counts, the orders walked from the moved subtask) cross many orders.
    model, demos, rows, pool = _problem(prior, likelihood, n, 5, **priors)
    got = _move_scores(rows, demos, model, _scratch(demos, model),
                       np.empty((3, n), dtype=np.int64), pool, _move_buffer(model),
                       move_scratch(demos, model),
                       np.zeros(demos.truth_t.shape[1], dtype=np.int32))
    done = ~np.isnan(got[..., 1])
    assert np.isfinite(got[..., 1][done]).sum() > 50
    np.testing.assert_array_equal(got[..., 0][done], got[..., 1][done])
