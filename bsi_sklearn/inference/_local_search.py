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

import numpy as np
from numba import njit

from bsi_sklearn.inference._gibbs_moves import sat_counts
from bsi_sklearn.likelihood import log_likelihood
from bsi_sklearn.priors import log_prior

__all__ = ["beam_search", "neighbourhood", "n_neighbours_max"]


@njit(cache=True, nogil=True)
def _score(row, demos, model, viol):
    # Exact log posterior of a row [tau, w1, parent], with viol as scratch.
    n_g, n = model.n_g, model.n
    tau, w1, parent = row[:n_g], row[n_g:n_g + n], row[n_g + n:]
    lp = log_prior(tau, w1, parent, model)
    if lp == -np.inf:
        return lp
    truth_t = demos.truth_t
    viol[:] = 0
    n_conj = 0
    for c in range(n_g + n):
        if row[c]:
            n_conj += 1
            for d in range(viol.shape[0]):
                viol[d] += 1 if truth_t[c, d] == 0 else 0
    for v in range(n):
        a = parent[v]
        while a >= 0:
            n_conj += 1
            c = n_g + n + a * n + v
            for d in range(viol.shape[0]):
                viol[d] += 1 if truth_t[c, d] == 0 else 0
            a = parent[a]
    ps, ns = sat_counts(viol, demos.w_pos, demos.w_neg)
    return lp + log_likelihood(ps, ns, demos.n_pos, demos.n_neg, n_conj, model.log_eps,
                               model.likelihood)


@njit(cache=True, nogil=True)
def _neighbours(row, model, out):
    # Every row one block away from ``row``, into out; returns their number.
    n_g, n = model.n_g, model.n
    base = n_g + n
    k = 0
    for j in range(n_g + (n if n <= 1 else 0)):
        out[k] = row
        out[k, j] = 1 - row[j]
        k += 1
    if n <= 1:
        return k
    child = np.empty(n, dtype=np.int64)
    for v in range(n):
        # v's place removed: its children hang from its parent (chains) or stay in its
        # subtree (forests, which move the whole subtree).
        rest = row[base:].astype(np.int64)
        in_s = np.zeros(n, dtype=np.bool_)
        if model.forest:
            for u in range(n):
                a = u
                while a >= 0 and a != v:
                    a = rest[a]
                in_s[u] = a == v
        else:
            in_s[v] = True
            for u in range(n):
                if rest[u] == v:
                    rest[u] = rest[v]
        rest[v] = -1
        child[:] = -1
        for u in range(n):
            if rest[u] >= 0:
                child[rest[u]] = u
        # Places: as a root / new chain, under (forests) or after (chains) any node outside
        # the subtree, and (chains) at the head of any chain.
        for u in range(-1, n):
            if u >= 0 and in_s[u]:
                continue
            for f in range(2):
                out[k] = row
                out[k, n_g + v] = f
                out[k, base:] = rest
                out[k, base + v] = u
                if u >= 0 and not model.forest and child[u] >= 0:
                    out[k, base + child[u]] = v
                k += 1
            if u >= 0 and not model.forest and rest[u] < 0:  # v at the head of u's chain
                for f in range(2):
                    out[k] = row
                    out[k, n_g + v] = f
                    out[k, base:] = rest
                    out[k, base + u] = v
                    k += 1
    return k


def n_neighbours_max(n_g, n):
    """The most neighbours one hypothesis has (rows of the buffer of ``_neighbours``)."""
    return n_g + n + n * 2 * (2 * n + 1)


@njit(cache=True, nogil=True)
def neighbourhood(rows, demos, model, floor):
    """The neighbours of ``rows`` whose log posterior is at least ``floor``, and those scores.

    Returns ``(neighbours, log_posteriors)``; a row may appear more than once, and rows of
    ``rows`` may be among them.
    """
    n_cols = rows.shape[1]
    per_row = model.n_g + model.n + model.n * 2 * (2 * model.n + 1)
    viol = np.zeros(demos.truth_t.shape[1], dtype=np.int32)
    buf = np.empty((per_row, n_cols), dtype=np.int64)
    out = np.empty((rows.shape[0] * per_row, n_cols), dtype=np.int16)
    out_lp = np.empty(out.shape[0])
    m = 0
    for i in range(rows.shape[0]):
        k = _neighbours(rows[i].astype(np.int64), model, buf)
        for j in range(k):
            lp = _score(buf[j], demos, model, viol)
            if lp >= floor:
                for c in range(n_cols):
                    out[m, c] = buf[j, c]
                out_lp[m] = lp
                m += 1
    return out[:m], out_lp[:m]


@njit(cache=True, nogil=True)
def _same(a, b):
    for i in range(a.shape[0]):
        if a[i] != b[i]:
            return False
    return True


@njit(cache=True, nogil=True)
def beam_search(start, demos, model, width, max_steps):
    """Beam search from the rows of ``start``; returns ``(best row, its log posterior)``."""
    n_g, n = model.n_g, model.n
    n_cols = n_g + 2 * n
    viol = np.zeros(demos.truth_t.shape[1], dtype=np.int32)
    per_row = n_g + n + n * 2 * (2 * n + 1)  # n_neighbours_max
    beam = start.copy()
    beam_lp = np.empty(beam.shape[0])
    for i in range(beam.shape[0]):
        beam_lp[i] = _score(beam[i], demos, model, viol)
    pool = np.empty((width * (per_row + 1), n_cols), dtype=np.int64)
    pool_lp = np.empty(pool.shape[0])
    nxt = np.empty((width, n_cols), dtype=np.int64)
    nxt_lp = np.empty(width)
    for _ in range(max_steps):
        m = 0
        for i in range(beam.shape[0]):
            pool[m] = beam[i]
            pool_lp[m] = beam_lp[i]
            m += 1
        for i in range(beam.shape[0]):
            k = _neighbours(beam[i], model, pool[m:])
            for j in range(m, m + k):
                pool_lp[j] = _score(pool[j], demos, model, viol)
            m += k
        order = np.argsort(-pool_lp[:m], kind="mergesort")
        kept = 0
        for j in order:
            if kept == width or pool_lp[j] == -np.inf:
                break
            dup = False
            for q in range(kept):
                if nxt_lp[q] == pool_lp[j] and _same(nxt[q], pool[j]):
                    dup = True
                    break
            if not dup:
                nxt[kept] = pool[j]
                nxt_lp[kept] = pool_lp[j]
                kept += 1
        changed = kept != beam.shape[0]
        if not changed:
            for q in range(kept):
                if nxt_lp[q] != beam_lp[q] or not _same(nxt[q], beam[q]):
                    changed = True
                    break
        beam = nxt[:kept].copy()
        beam_lp = nxt_lp[:kept].copy()
        if not changed:
            break
    return beam[0], beam_lp[0]
