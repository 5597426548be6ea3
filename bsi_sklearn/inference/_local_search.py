"""Local search around hypotheses: beam search for an optimum, and one-block neighbourhoods.

A neighbour of a hypothesis changes one block of the Gibbs sampler: one global bit, or one
subtask's place in the order structure together with its eventual bit (one eventual bit when
there is no order to change; :mod:`bsi_sklearn.inference._block_moves`). Every neighbour is
scored exactly (the log posterior of :func:`bsi_sklearn.inference._chain_kernel.score_one`),
not through the chains' incremental bookkeeping. No random numbers.

- :func:`beam_search`: a beam of hypotheses, grown from given rows; every step scores every
  neighbour of every hypothesis in the beam and keeps the best ``width`` distinct ones, until
  the beam no longer changes. It gives the deterministic optimum that MCMC chains are checked
  against (they must not sit on a worse mode) and the level their burn-in waits for.
- :func:`neighbourhood`: the neighbours of given rows above a log-posterior floor, which
  complete the support of an MCMC posterior where it is flat (states each too improbable for
  the chains to visit, but many): :func:`complete_support` picks the rows.
"""

import math
from typing import NamedTuple

import numpy as np
from numba import njit

from bsi_sklearn._jit import helper
from bsi_sklearn._unique_rows import row_keys
from bsi_sklearn.inference._block_moves import (
    N_MOVE,
    enumerate_moves,
    flip_scratch,
    move_scratch,
    n_flip_bits,
    n_neighbours_max,
    neighbours,
    prepare_flips,
    prepare_moves,
    put_move,
    put_row,
    score_flip,
    score_moved,
    write_move,
)
from bsi_sklearn.inference._chain_kernel import fill_viol
from bsi_sklearn.inference._row_counts import sat_counts
from bsi_sklearn.model.likelihood import log_likelihood
from bsi_sklearn.model.priors import log_prior, log_prior_globals
from bsi_sklearn.model.state_layout import split_state, state_width

__all__ = ["beam_search", "neighbourhood", "complete_support", "n_neighbours_max"]

#: The support is completed with the neighbours of its most probable states holding this much
#: of its mass (at most ``COMPLETE_SOURCES`` of them, within a budget of this many clause-row
#: operations, about 0.3 s), keeping neighbours less than ``COMPLETE_FLOOR`` (log 1e12) below
#: the most probable state.
COMPLETE_MASS = 0.99
COMPLETE_SOURCES = 2000
COMPLETE_WORK = 3e8
COMPLETE_FLOOR = math.log(1e12)


class _Scratch(NamedTuple):
    viol: np.ndarray      # (D,) int32
    tau: np.ndarray       # (n_g,) int64: a row's parts, contiguous, as score_one's callers
    w1: np.ndarray        # (n,) int64   pass them (log_prior compiled once for both)
    parent: np.ndarray    # (n,) int64


def _scratch(demos, model):
    # Allocated by Python: a numpy allocation inside a kernel is one more compilation.
    return _Scratch(np.zeros(demos.truth_t.shape[1], dtype=np.int32),
                    np.empty(model.n_g, dtype=np.int64), np.empty(model.n, dtype=np.int64),
                    np.empty(model.n, dtype=np.int64))


@helper
def _load(row, model, scratch):
    # A row's parts into the scratch arrays, and its log prior (log_prior's arithmetic).
    n_g, n = model.n_g, model.n
    tau, w1, parent = scratch.tau, scratch.w1, scratch.parent
    row_tau, row_w1, row_parent = split_state(row, n_g, n)
    for j in range(n_g):
        tau[j] = row_tau[j]
    for w in range(n):
        w1[w] = row_w1[w]
        parent[w] = row_parent[w]
    return log_prior(tau, w1, parent, model)


@helper
def _score(row, demos, model, scratch):
    # Exact log posterior of a row [tau, w1, parent].
    lp = _load(row, model, scratch)
    if lp == -np.inf:
        return lp
    n_conj = fill_viol(scratch.viol, scratch.tau, scratch.w1, scratch.parent, demos.truth_t,
                       model)
    ps, ns = sat_counts(scratch.viol, demos.w_pos, demos.w_neg)
    return lp + log_likelihood(ps, ns, demos.n_pos, demos.n_neg, n_conj, model.log_eps,
                               model.likelihood, model.flips)


def neighbourhood(rows, demos, model, floor):
    """The neighbours of ``rows`` whose log posterior is at least ``floor``, and those scores.

    Returns ``(neighbours, log_posteriors)``; a row may appear more than once, and rows of
    ``rows`` may be among them.
    """
    per_row = n_neighbours_max(model.n_g, model.n)
    n_cols = rows.shape[1]
    out = np.empty((rows.shape[0] * per_row, n_cols), dtype=np.int16)
    out_lp = np.empty(out.shape[0])
    m = _neighbourhood(rows, demos, model, float(floor), _scratch(demos, model),
                       np.empty((3, model.n), dtype=np.int64),
                       np.empty((per_row, n_cols), dtype=np.int64),
                       np.empty((per_row, N_MOVE), dtype=np.int64), out, out_lp)
    return out[:m], out_lp[:m]


@njit(cache=True, nogil=True)
def _neighbourhood(rows, demos, model, floor, scratch, work, buf, moves, out, out_lp):
    n_cols = rows.shape[1]
    m = np.int64(0)  # counters start as int64, not literal 0s: one compilation each
    for i in range(rows.shape[0]):
        k = neighbours(rows[i], model, buf, np.int64(0), work, moves)
        for j in range(k):
            lp = _score(buf[j], demos, model, scratch)
            if lp >= floor:
                put_row(out, m, buf[j], n_cols)
                out_lp[m] = lp
                m += 1
    return m


@helper
def _same(a, b):
    for i in range(a.shape[0]):
        if a[i] != b[i]:
            return False
    return True


class _Beam(NamedTuple):
    moves: np.ndarray    # (width * (n_neighbours_max + 1), N_MOVE) int64: the beam's moves
    source: np.ndarray   # (same,) int64: the beam row each move starts from
    pool_lp: np.ndarray  # their log posteriors
    taken: np.ndarray    # bool
    beam: np.ndarray     # (width, n_cols) int64
    beam_lp: np.ndarray
    nxt: np.ndarray      # (width, n_cols) int64: the next beam
    nxt_lp: np.ndarray
    row: np.ndarray      # (1, n_cols) int64: a move's row, written out


def beam_search(start, demos, model, width, max_steps):
    """Beam search from the rows of ``start``; returns ``(best row, its log posterior)``."""
    n_cols = state_width(model.n_g, model.n)
    rows = width * (n_neighbours_max(model.n_g, model.n) + 1)
    bufs = _Beam(np.empty((rows, N_MOVE), dtype=np.int64), np.empty(rows, dtype=np.int64),
                 np.empty(rows), np.empty(rows, dtype=np.bool_),
                 np.empty((width, n_cols), dtype=np.int64), np.empty(width),
                 np.empty((width, n_cols), dtype=np.int64), np.empty(width),
                 np.empty((1, n_cols), dtype=np.int64))
    lp = _beam_search(start, demos, model, int(width), int(max_steps), _scratch(demos, model),
                      bufs, move_scratch(demos, model), flip_scratch(demos, model))
    return bufs.beam[0].copy(), lp


@njit(cache=True, nogil=True)
def _beam_search(start, demos, model, width, max_steps, scratch, bufs, moves, flips):
    n_g, n = model.n_g, model.n
    n_cols = state_width(n_g, n)
    n_bits = n_flip_bits(model)
    pool, source, pool_lp, taken, beam, beam_lp, nxt, nxt_lp, row = bufs
    work, viol = moves.work, scratch.viol  # (detach's structure; the beam row's counts)
    n_beam = min(width, start.shape[0])
    for i in range(n_beam):
        put_row(beam, i, start[i], n_cols)
        beam_lp[i] = _score(beam[i], demos, model, scratch)
    for _ in range(max_steps):
        m = np.int64(0)
        for i in range(n_beam):
            put_move(pool, m, -1, -1, 0, 0)  # the beam row itself
            source[m] = i
            pool_lp[m] = beam_lp[i]
            m += 1
        for i in range(n_beam):
            k = enumerate_moves(beam[i], model, pool, m, work)
            for j in range(m, k):
                source[j] = i
            # The bit flips first: scored from the beam row's violation counts as bitsets
            # (hundreds of pattern clauses make hundreds of them, each O(words) instead of
            # O(D x conjuncts)).
            # The structure moves of each subtask from those counts less the subtask's
            # clauses, as bitsets (prepare_moves, score_moved).
            _load(beam[i], model, scratch)
            n_conj = fill_viol(viol, scratch.tau, scratch.w1, scratch.parent, demos.truth_t,
                               model)
            prepare_flips(viol, model, scratch, flips)
            for j in range(m, m + n_bits):
                pool_lp[j] = score_flip(j - m, n_conj, demos, model, scratch, flips)
            lp_g = log_prior_globals(scratch.tau, model)
            v = -1
            rest = (np.int64(0), 0.0, 0.0, 0.0, 0.0)
            for j in range(m + n_bits, k):
                if pool[j, 1] != v:
                    v = pool[j, 1]
                    rest = prepare_moves(beam[i], v, viol, n_conj, demos, model, moves)
                pool_lp[j] = score_moved(beam[i], pool[j], lp_g, rest, demos, model, scratch,
                                         moves)
            m = k
        # The best `width` distinct rows, in decreasing order (the first of ties).
        taken[:m] = False
        kept = np.int64(0)
        while kept < width:
            j = -1
            for i in range(m):
                if not taken[i] and pool_lp[i] > -np.inf and (j < 0 or pool_lp[i] > pool_lp[j]):
                    j = i
            if j < 0:
                break
            taken[j] = True
            write_move(beam[source[j]], pool[j], model, row, 0, work)
            dup = False
            for q in range(kept):
                if nxt_lp[q] == pool_lp[j] and _same(nxt[q], row[0]):
                    dup = True
                    break
            if not dup:
                put_row(nxt, kept, row[0], n_cols)
                nxt_lp[kept] = pool_lp[j]
                kept += 1
        changed = kept != n_beam
        if not changed:
            for q in range(kept):
                if nxt_lp[q] != beam_lp[q] or not _same(nxt[q], beam[q]):
                    changed = True
                    break
        for q in range(kept):
            put_row(beam, q, nxt[q], n_cols)
            beam_lp[q] = nxt_lp[q]
        n_beam = kept
        if not changed:
            break
    return beam_lp[0]


def complete_support(uniq, scores, demos, model, complete=None):
    """The one-block neighbours that complete an MCMC posterior's support where it is flat.

    The neighbours of the support's most probable states (those holding ``COMPLETE_MASS`` of
    it, within the caps) less than ``COMPLETE_FLOOR`` below the most probable, with their
    exact log posterior (:func:`neighbourhood`); the caller drops those already in it.
    ``complete(floor)``, when given, returns the keys (:func:`~bsi_sklearn._unique_rows.row_keys`)
    of states whose neighbours at or above ``floor`` are all in the support already (the
    closure's, :meth:`~._closure.Closure.complete`): those are not weighed again, which
    leaves the support completed the same. Returns ``(rows, log_posteriors)``.
    """
    probs = np.exp(scores - scores.max())
    probs /= probs.sum()
    order = np.argsort(-scores, kind="stable")
    cost = max(1, n_neighbours_max(model.n_g, model.n) * demos.truth_t.shape[0]) * \
        demos.truth_t.shape[1]
    n_src = min(int(np.searchsorted(np.cumsum(probs[order]), COMPLETE_MASS)) + 1,
                max(1, int(COMPLETE_WORK // cost)), COMPLETE_SOURCES, len(order))
    floor = scores.max() - COMPLETE_FLOOR
    picked = order[:n_src]
    known = complete(floor) if complete is not None else frozenset()
    if known:
        picked = picked[[key not in known for key in row_keys(uniq[picked])]]
    sources = np.ascontiguousarray(uniq[picked], dtype=np.int64)
    return neighbourhood(sources, demos, model, floor)
