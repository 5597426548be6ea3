"""Local search around hypotheses: beam search for an optimum, and one-block neighbourhoods.

A neighbour of a hypothesis changes one block of the Gibbs sampler: one global bit, or one
subtask's place in the order structure together with its eventual bit (one eventual bit when
there is no order to change). Every neighbour is scored exactly, from scratch (the log
posterior of :func:`bsi_sklearn.inference._chain_kernel.score_one`), not through the chains'
incremental bookkeeping. No random numbers.

- :func:`beam_search`: a beam of hypotheses, grown from given rows; every step scores every
  neighbour of every hypothesis in the beam and keeps the best ``width`` distinct ones, until
  the beam no longer changes. It gives the deterministic optimum that MCMC chains are checked
  against (they must not sit on a worse mode) and the level their burn-in waits for.
- :func:`neighbourhood`: the neighbours of given rows above a log-posterior floor, which
  complete the support of an MCMC posterior where it is flat (states each too improbable for
  the chains to visit, but many).
"""

from typing import NamedTuple

import numpy as np
from numba import njit

from bsi_sklearn._jit import helper
from bsi_sklearn.inference._chain_kernel import add_structure_viol, fill_viol
from bsi_sklearn.inference._gibbs_moves import add_pair
from bsi_sklearn.inference._row_counts import flip_sums, sat_counts, weighted_popcount, zero_mask
from bsi_sklearn.model.clauses import clause_index_eventual, clause_index_order
from bsi_sklearn.model.likelihood import log_likelihood
from bsi_sklearn.model.priors import (
    is_forest,
    log_prior,
    log_prior_globals,
    log_prior_structure,
    log_prior_subset,
)
from bsi_sklearn.model.state_layout import parent_offset, split_state, state_width, w1_offset

__all__ = ["beam_search", "neighbourhood", "n_neighbours_max"]


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
                               model.likelihood, model.flip_a, model.flip_b)


@helper
def _score_flip(b, viol, n_conj, demos, model, scratch):
    # _score of the row loaded in `scratch` (_load) with inclusion bit b flipped, from that
    # row's violation counts `viol` and conjuncts `n_conj`: the same number, bit for bit (the
    # prior by log_prior over the same arrays, the bit flipped in place and back; the
    # satisfied counts are sums of whole numbers, exact in any order, so the likelihood gets
    # the same arguments), in O(D + n_g) instead of O(D x conjuncts), the row never copied.
    n_g = model.n_g
    bits = scratch.tau if b < n_g else scratch.w1
    i = b if b < n_g else b - n_g
    inc = bits[i]  # the bit in the loaded row
    bits[i] = 1 - inc
    lp = log_prior(scratch.tau, scratch.w1, scratch.parent, model)
    bits[i] = inc
    if lp == -np.inf:
        return lp
    c = b if b < n_g else clause_index_eventual(b - n_g, n_g)
    ps_out, ns_out, ps_in, ns_in = flip_sums(viol, demos.truth_t, c, inc, demos.w_pos,
                                             demos.w_neg)
    if inc:
        return lp + log_likelihood(ps_out, ns_out, demos.n_pos, demos.n_neg, n_conj - 1,
                                   model.log_eps, model.likelihood, model.flip_a, model.flip_b)
    return lp + log_likelihood(ps_in, ns_in, demos.n_pos, demos.n_neg, n_conj + 1,
                               model.log_eps, model.likelihood, model.flip_a, model.flip_b)


class _Moves(NamedTuple):
    viol: np.ndarray   # (D,) int32: the row's counts without the moved subtask's clauses
    zrest: np.ndarray  # (1, W) uint64: the rows violating none of those clauses
    mask: np.ndarray   # (1, W) uint64: a candidate's rows
    work: np.ndarray   # (3, n) int64: _detach's structure without v, successors, moved set


def _moves(demos, model):
    n_words = demos.bits.shape[1]
    return _Moves(np.zeros(demos.truth_t.shape[1], dtype=np.int32),
                  np.zeros((1, n_words), dtype=np.uint64), np.zeros((1, n_words), dtype=np.uint64),
                  np.zeros((3, model.n), dtype=np.int64))


# A move is four numbers (b, v, u, g): b >= 0 flips inclusion bit b; otherwise subtask v
# leaves its place (_detach) and is put back under / after u (-1: a root, a new chain) with
# eventual bit g & 1, or (g & 2, chains) at the head of u's chain; (-1, -1, 0, 0) is the row
# itself. The beam search keeps moves, not rows: a row is written out only when kept.
N_MOVE = 4


@helper
def _detach(row, v, model, work):
    # Subtask v's place removed from the row's structure, into work[0]: v's children hang from
    # its parent (chains) or stay in its subtree (forests, which move the whole subtree).
    # work[1]: the successors in that structure; work[2]: the set that moves (v; v's subtree).
    n_g, n = model.n_g, model.n
    base = parent_offset(n_g, n)
    rest, child, in_s = work[0], work[1], work[2]
    for u in range(n):
        rest[u] = row[base + u]
        in_s[u] = 0
    if is_forest(model):
        for u in range(n):
            a = u
            while a >= 0 and a != v:
                a = rest[a]
            in_s[u] = 1 if a == v else 0
    else:
        in_s[v] = 1
        for u in range(n):
            if rest[u] == v:
                rest[u] = rest[v]
    rest[v] = -1
    for u in range(n):
        child[u] = -1
    for u in range(n):
        if rest[u] >= 0:
            child[rest[u]] = u


@helper
def _place(v, u, g, model, work, parent):
    # The structure of move (., v, u, g) into `parent`, from _detach(row, v)'s work.
    rest, child = work[0], work[1]
    for w in range(model.n):
        parent[w] = rest[w]
    if g & 2:  # v at the head of u's chain
        parent[u] = v
    else:
        parent[v] = u
        if u >= 0 and not is_forest(model) and child[u] >= 0:
            parent[child[u]] = v


@helper
def _put_move(moves, k, b, v, u, g):
    moves[k, 0] = b
    moves[k, 1] = v
    moves[k, 2] = u
    moves[k, 3] = g


@helper
def _enumerate_moves(row, model, moves, k, work):
    # Every move one block away from ``row``, into moves[k:]; returns the new k. The inclusion
    # bits first (tau's, and W1's too when there is no order to move them with), then every
    # subtask's places: as a root / new chain, under (forests) or after (chains) any node
    # outside what moves, and (chains) at the head of any chain; each with F(v) out and in.
    n = model.n
    for j in range(_n_bits(model)):
        _put_move(moves, k, j, -1, 0, 0)
        k += 1
    if n <= 1:
        return k
    rest, in_s = work[0], work[2]
    for v in range(n):
        _detach(row, v, model, work)
        for u in range(-1, n):
            if u >= 0 and in_s[u]:
                continue
            for f in range(2):
                _put_move(moves, k, -1, v, u, f)
                k += 1
            if u >= 0 and not is_forest(model) and rest[u] < 0:
                for f in range(2):
                    _put_move(moves, k, -1, v, u, f | 2)
                    k += 1
    return k


@helper
def _write_move(row, move, model, out, i, work):
    # The row `move` makes of `row`, into out[i].
    n_g, n = model.n_g, model.n
    n_cols = state_width(n_g, n)
    _put(out, i, row, n_cols)
    b, v = move[0], move[1]
    if b >= 0:
        out[i, b] = 1 - row[b]
    elif v >= 0:
        _detach(row, v, model, work)
        out[i, w1_offset(n_g) + v] = move[3] & 1
        base = parent_offset(n_g, n)
        _place(v, move[2], move[3], model, work, out[i, base:])


@helper
def _neighbours(row, model, out, k, work, moves):
    # Every row one block away from ``row``, into out[k:] (its moves into moves[k:]); returns
    # the new k. work: (3, n) int64 scratch.
    k_end = _enumerate_moves(row, model, moves, k, work)
    for i in range(k, k_end):
        _write_move(row, moves[i], model, out, i, work)
    return k_end


@helper
def _cross_pairs(parent, in_s, take_out, viol, mask, demos, model):
    # The order clauses of `parent` between the moved set and the rest (an ancestor on one
    # side, its descendant on the other): taken out of `viol` (take_out), or ANDed into
    # `mask`. Returns their number.
    n_g, n = model.n_g, model.n
    count = 0
    for y in range(n):
        a = parent[y]
        while a >= 0:
            if in_s[a] != in_s[y]:
                c = clause_index_order(a, y, n_g, n)
                if take_out:
                    add_pair(viol, demos.truth_t, c, np.int64(-1))
                else:
                    for w in range(mask.shape[1]):
                        mask[0, w] &= demos.bits[c, w]
                count += 1
            a = parent[a]
    return count


@helper
def _prepare_moves(row, v, viol, n_conj, demos, model, moves):
    # For the structure moves of subtask v of `row` (violation counts `viol`, `n_conj`
    # conjuncts): its place detached (moves.work), and the rows that violate nothing once v's
    # eventual clause and the orders across the moved set are out (a move only adds such
    # clauses back; every other clause of the row stays). Returns the conjuncts left.
    n_g, n = model.n_g, model.n
    _detach(row, v, model, moves.work)
    rest = moves.viol
    for d in range(rest.shape[0]):
        rest[d] = viol[d]
    if row[w1_offset(n_g) + v]:
        add_pair(rest, demos.truth_t, clause_index_eventual(v, n_g), np.int64(-1))
        n_conj -= 1
    _, _, parent = split_state(row, n_g, n)
    n_conj -= _cross_pairs(parent, moves.work[2], True, rest, moves.mask, demos, model)
    zero_mask(rest, moves.zrest)
    return n_conj


@helper
def _score_moved(row, move, lp_g, n_conj_rest, demos, model, scratch, moves):
    # _score of the row structure move `move` makes of `row`, prepared by _prepare_moves
    # (`n_conj_rest` conjuncts left, the row's global clauses' log prior `lp_g`): the same
    # number, bit for bit (log_prior's sum in its order; the satisfied counts are whole
    # numbers, equal as bitset popcounts), in O(orders across the move x words) instead of
    # O(D x conjuncts), the row never written out.
    n_g, n = model.n_g, model.n
    w1, parent, mask = scratch.w1, scratch.parent, moves.mask
    v, g = move[1], move[3]
    _, row_w1, _ = split_state(row, n_g, n)
    for w in range(n):
        w1[w] = row_w1[w]
    w1[v] = g & 1
    _place(v, move[2], g, model, moves.work, parent)
    lp = (lp_g + log_prior_subset(w1.sum(), w1.shape[0], model.p_eventual)
          + log_prior_structure(parent, model))
    if lp == -np.inf:
        return lp
    for w in range(mask.shape[1]):
        mask[0, w] = moves.zrest[0, w]
    n_conj = n_conj_rest
    if w1[v]:
        c = clause_index_eventual(v, n_g)
        for w in range(mask.shape[1]):
            mask[0, w] &= demos.bits[c, w]
        n_conj += 1
    n_conj += _cross_pairs(parent, moves.work[2], False, moves.viol, mask, demos, model)
    ps = 0
    ns = 0
    for w in range(mask.shape[1]):
        word = mask[0, w]
        if word != 0:
            ps += weighted_popcount(word, demos.pos_planes, w)
            ns += weighted_popcount(word, demos.neg_planes, w)
    return lp + log_likelihood(float(ps), float(ns), demos.n_pos, demos.n_neg, n_conj,
                               model.log_eps, model.likelihood, model.flip_a, model.flip_b)


@helper
def _n_bits(model):
    # The inclusion bits _neighbours flips first: tau's, and W1's when there is no order.
    return parent_offset(model.n_g, model.n) if model.n <= 1 else w1_offset(model.n_g)


@helper
def _put(out, k, row, n_cols):
    for c in range(n_cols):
        out[k, c] = row[c]


def n_neighbours_max(n_g, n):
    """The most neighbours one hypothesis has (rows of the buffer of ``_neighbours``)."""
    return n_g + n + n * 2 * (2 * n + 1)


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
        k = _neighbours(rows[i], model, buf, np.int64(0), work, moves)
        for j in range(k):
            lp = _score(buf[j], demos, model, scratch)
            if lp >= floor:
                _put(out, m, buf[j], n_cols)
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
                      np.empty((3, model.n), dtype=np.int64), bufs,
                      np.zeros((2, demos.truth_t.shape[1]), dtype=np.int32),
                      _moves(demos, model))
    return bufs.beam[0].copy(), lp


@njit(cache=True, nogil=True)
def _beam_search(start, demos, model, width, max_steps, scratch, work, bufs, counts, moves):
    n_g, n = model.n_g, model.n
    n_cols = state_width(n_g, n)
    n_bits = _n_bits(model)
    pool, source, pool_lp, taken, beam, beam_lp, nxt, nxt_lp, row = bufs
    n_beam = min(width, start.shape[0])
    for i in range(n_beam):
        _put(beam, i, start[i], n_cols)
        beam_lp[i] = _score(beam[i], demos, model, scratch)
    for _ in range(max_steps):
        m = np.int64(0)
        for i in range(n_beam):
            _put_move(pool, m, -1, -1, 0, 0)  # the beam row itself
            source[m] = i
            pool_lp[m] = beam_lp[i]
            m += 1
        for i in range(n_beam):
            k = _enumerate_moves(beam[i], model, pool, m, work)
            for j in range(m, k):
                source[j] = i
            # The bit flips first: scored from the beam row's violation counts (hundreds of
            # pattern clauses make hundreds of them, each O(D) instead of O(D x conjuncts)).
            # The structure moves of each subtask from those counts less the subtask's
            # clauses, as bitsets (_prepare_moves, _score_moved).
            b_tau, b_w1, b_parent = split_state(beam[i], n_g, n)
            viol, viol_g = counts[0], counts[1]
            scratch.w1[:] = 0
            scratch.parent[:] = -1
            n_g_conj = fill_viol(viol_g, b_tau, scratch.w1, scratch.parent, demos.truth_t,
                                 model)
            viol[:] = viol_g
            n_conj = n_g_conj + add_structure_viol(viol, b_w1, b_parent, demos.truth_t, model)
            _load(beam[i], model, scratch)
            for j in range(m, m + n_bits):
                pool_lp[j] = _score_flip(j - m, viol, n_conj, demos, model, scratch)
            lp_g = log_prior_globals(b_tau, model)
            v = -1
            n_conj_rest = 0
            for j in range(m + n_bits, k):
                if pool[j, 1] != v:
                    v = pool[j, 1]
                    n_conj_rest = _prepare_moves(beam[i], v, viol, n_conj, demos, model, moves)
                pool_lp[j] = _score_moved(beam[i], pool[j], lp_g, n_conj_rest, demos, model,
                                          scratch, moves)
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
            _write_move(beam[source[j]], pool[j], model, row, 0, work)
            dup = False
            for q in range(kept):
                if nxt_lp[q] == pool_lp[j] and _same(nxt[q], row[0]):
                    dup = True
                    break
            if not dup:
                _put(nxt, kept, row[0], n_cols)
                nxt_lp[kept] = pool_lp[j]
                kept += 1
        changed = kept != n_beam
        if not changed:
            for q in range(kept):
                if nxt_lp[q] != beam_lp[q] or not _same(nxt[q], beam[q]):
                    changed = True
                    break
        for q in range(kept):
            _put(beam, q, nxt[q], n_cols)
            beam_lp[q] = nxt_lp[q]
        n_beam = kept
        if not changed:
            break
    return beam_lp[0]
