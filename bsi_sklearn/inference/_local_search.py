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
from bsi_sklearn.inference._gibbs_moves import flip_sums, sat_counts
from bsi_sklearn.model.clauses import clause_index_eventual
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


@helper
def _score_moved(row, lp_g, viol_g, n_g_conj, demos, model, scratch):
    # _score of `row`, which keeps the global bits of a row whose G and pattern clauses alone
    # have violation counts `viol_g` (`n_g_conj` of them, log prior `lp_g`): the same number,
    # bit for bit (log_prior's sum in its order, the satisfied counts whole numbers), without
    # recounting the global clauses, hundreds with pattern clauses, for every structure move.
    n_g, n = model.n_g, model.n
    w1, parent, viol = scratch.w1, scratch.parent, scratch.viol
    _, row_w1, row_parent = split_state(row, n_g, n)
    for w in range(n):
        w1[w] = row_w1[w]
        parent[w] = row_parent[w]
    lp = (lp_g + log_prior_subset(w1.sum(), w1.shape[0], model.p_eventual)
          + log_prior_structure(parent, model))
    if lp == -np.inf:
        return lp
    for d in range(viol.shape[0]):
        viol[d] = viol_g[d]
    n_conj = n_g_conj + add_structure_viol(viol, w1, parent, demos.truth_t, model)
    ps, ns = sat_counts(viol, demos.w_pos, demos.w_neg)
    return lp + log_likelihood(ps, ns, demos.n_pos, demos.n_neg, n_conj, model.log_eps,
                               model.likelihood, model.flip_a, model.flip_b)


@helper
def _n_bits(model):
    # The inclusion bits _neighbours flips first: tau's, and W1's when there is no order.
    return parent_offset(model.n_g, model.n) if model.n <= 1 else w1_offset(model.n_g)


@helper
def _put(out, k, row, n_cols):
    for c in range(n_cols):
        out[k, c] = row[c]


@helper
def _neighbours(row, model, out, k, work):
    # Every row one block away from ``row``, into out[k:]; returns the new k. work: (3, n)
    # int64 scratch (the structure without v, its successors, v's subtree).
    n_g, n = model.n_g, model.n
    base, n_cols = parent_offset(n_g, n), state_width(n_g, n)
    # The inclusion bits: tau's, and W1's too when there is no order to move them with.
    for j in range(_n_bits(model)):
        _put(out, k, row, n_cols)
        out[k, j] = 1 - row[j]
        k += 1
    if n <= 1:
        return k
    rest, child, in_s = work[0], work[1], work[2]
    for v in range(n):
        # v's place removed: its children hang from its parent (chains) or stay in its
        # subtree (forests, which move the whole subtree).
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
        # Places: as a root / new chain, under (forests) or after (chains) any node outside
        # the subtree, and (chains) at the head of any chain.
        for u in range(-1, n):
            if u >= 0 and in_s[u]:
                continue
            for f in range(2):
                _put(out, k, row, base)
                out[k, w1_offset(n_g) + v] = f
                for w in range(n):
                    out[k, base + w] = rest[w]
                out[k, base + v] = u
                if u >= 0 and not is_forest(model) and child[u] >= 0:
                    out[k, base + child[u]] = v
                k += 1
            if u >= 0 and not is_forest(model) and rest[u] < 0:  # v at the head of u's chain
                for f in range(2):
                    _put(out, k, row, base)
                    out[k, w1_offset(n_g) + v] = f
                    for w in range(n):
                        out[k, base + w] = rest[w]
                    out[k, base + u] = v
                    k += 1
    return k


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
                       np.empty((per_row, n_cols), dtype=np.int64), out, out_lp)
    return out[:m], out_lp[:m]


@njit(cache=True, nogil=True)
def _neighbourhood(rows, demos, model, floor, scratch, work, buf, out, out_lp):
    n_cols = rows.shape[1]
    m = np.int64(0)  # counters start as int64, not literal 0s: one compilation each
    for i in range(rows.shape[0]):
        k = _neighbours(rows[i], model, buf, np.int64(0), work)
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
    pool: np.ndarray     # (width * (n_neighbours_max + 1), n_cols) int64: beam and neighbours
    pool_lp: np.ndarray  # their log posteriors
    taken: np.ndarray    # bool
    beam: np.ndarray     # (width, n_cols) int64
    beam_lp: np.ndarray
    nxt: np.ndarray      # (width, n_cols) int64: the next beam
    nxt_lp: np.ndarray


def beam_search(start, demos, model, width, max_steps):
    """Beam search from the rows of ``start``; returns ``(best row, its log posterior)``."""
    n_cols = state_width(model.n_g, model.n)
    rows = width * (n_neighbours_max(model.n_g, model.n) + 1)
    bufs = _Beam(np.empty((rows, n_cols), dtype=np.int64), np.empty(rows),
                 np.empty(rows, dtype=np.bool_), np.empty((width, n_cols), dtype=np.int64),
                 np.empty(width), np.empty((width, n_cols), dtype=np.int64), np.empty(width))
    lp = _beam_search(start, demos, model, int(width), int(max_steps), _scratch(demos, model),
                      np.empty((3, model.n), dtype=np.int64), bufs,
                      np.zeros((2, demos.truth_t.shape[1]), dtype=np.int32))
    return bufs.beam[0].copy(), lp


@njit(cache=True, nogil=True)
def _beam_search(start, demos, model, width, max_steps, scratch, work, bufs, counts):
    n_g, n = model.n_g, model.n
    n_cols = state_width(n_g, n)
    n_bits = _n_bits(model)
    pool, pool_lp, taken, beam, beam_lp, nxt, nxt_lp = bufs
    n_beam = min(width, start.shape[0])
    for i in range(n_beam):
        _put(beam, i, start[i], n_cols)
        beam_lp[i] = _score(beam[i], demos, model, scratch)
    for _ in range(max_steps):
        m = np.int64(0)
        for i in range(n_beam):
            _put(pool, m, beam[i], n_cols)
            pool_lp[m] = beam_lp[i]
            m += 1
        for i in range(n_beam):
            k = _neighbours(beam[i], model, pool, m, work)
            # The bit flips first: scored from the beam row's violation counts (hundreds of
            # pattern clauses make hundreds of them, each O(D) instead of O(D x conjuncts)).
            # The beam row's global clauses counted once (its global bits alone: no eventual,
            # no order), which the structure moves keep; its own counts add the rest.
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
            for j in range(m + n_bits, k):
                pool_lp[j] = _score_moved(pool[j], lp_g, viol_g, n_g_conj, demos, model,
                                          scratch)
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
            dup = False
            for q in range(kept):
                if nxt_lp[q] == pool_lp[j] and _same(nxt[q], pool[j]):
                    dup = True
                    break
            if not dup:
                _put(nxt, kept, pool[j], n_cols)
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
