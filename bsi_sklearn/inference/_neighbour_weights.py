"""One-block neighbourhoods weighed the way a Gibbs update weighs them.

:func:`bsi_sklearn.inference._local_search.neighbourhood` scores every neighbour of a
hypothesis from scratch, every clause over every demonstration: at 40 activities (their 40
negations global candidates only) one hypothesis has about 6,600 neighbours and 1,700
clauses, about 10^10 operations per hypothesis over 700 demonstrations. A Gibbs update
weighs the same neighbours incrementally: a bit's two values from the demonstrations' counts
of violated clauses, a subtask's places from bitsets over the demonstrations that violate
nothing else (:mod:`bsi_sklearn.inference._gibbs_moves`). :func:`weigh_neighbours` runs
those moves' candidate code (:func:`~._row_counts.flip_sums`,
:func:`~._gibbs_moves.chain_candidates`, :func:`~._gibbs_moves.forest_candidates`) at
``beta = 1`` on every block of every given hypothesis, keeps the neighbours it weighs within
a margin of the floor, and scores those again from scratch, so the scores it returns are the
exact ones and the set is :func:`~._local_search.neighbourhood`'s (tested against it for
every prior).
"""

from typing import NamedTuple

import numpy as np
from numba import njit

from bsi_sklearn._jit import helper
from bsi_sklearn.inference._chain_kernel import fill_viol, make_buffers
from bsi_sklearn.inference._gibbs_moves import chain_candidates, forest_candidates
from bsi_sklearn.inference._local_search import _score, _scratch, n_neighbours_max
from bsi_sklearn.inference._row_counts import flip_sums
from bsi_sklearn.model.clauses import clause_index_eventual
from bsi_sklearn.model.likelihood import log_likelihood
from bsi_sklearn.model.priors import (
    global_inclusion,
    is_forest,
    log_prior_globals,
    log_prior_structure,
    log_prior_subset,
    n_plain_globals,
    subset_inclusion,
)
from bsi_sklearn.model.state_layout import parent_offset, state_width, w1_offset

__all__ = ["weigh_neighbours", "neighbours_within", "NeighbourWeigher", "neighbour_work",
           "MARGIN"]

#: Neighbours weighed within this many nats below the floor are scored again from scratch:
#: the incremental and the from-scratch sums of the same terms differ by rounding only.
MARGIN = 1e-6


class _Work(NamedTuple):
    tau: np.ndarray        # (n_g,) int64: the hypothesis being moved
    w1: np.ndarray         # (n,) int64
    parent: np.ndarray     # (n,) int64
    viol: np.ndarray       # (D,) int32: clauses of it each row violates
    keep_w1: np.ndarray    # (n,) int64: the source hypothesis, restored after every block
    keep_parent: np.ndarray
    keep_viol: np.ndarray  # (D,) int32
    row: np.ndarray        # (n_cols,) int64: a neighbour being written


def _work(demos, model):
    n_g, n, d = model.n_g, model.n, demos.truth_t.shape[1]
    return _Work(np.empty(n_g, dtype=np.int64), np.empty(n, dtype=np.int64),
                 np.empty(n, dtype=np.int64), np.zeros(d, dtype=np.int32),
                 np.empty(n, dtype=np.int64), np.empty(n, dtype=np.int64),
                 np.zeros(d, dtype=np.int32), np.empty(state_width(n_g, n), dtype=np.int64))


def weigh_neighbours(rows, demos, model, floor):
    """The neighbours of ``rows`` whose log posterior is at least ``floor``, and those scores.

    The same rows and scores as :func:`~._local_search.neighbourhood` (possibly in another
    order; a row may appear more than once; a row of ``rows`` is never its own neighbour),
    for the price of one Gibbs sweep per row of ``rows`` plus one exact score per neighbour
    kept.

    Returns
    -------
    neighbours : ndarray of shape (m, n_cols), int16
    log_posteriors : ndarray of shape (m,)
    """
    found, scores, _, _, _ = neighbours_within(rows, demos, model, floor)
    return found, scores


def neighbour_work(demos, model):
    """``(per row, per neighbour kept)``: the work :func:`neighbours_within` counts.

    A row costs its violation counts (every clause over every unique demonstration) and the
    weighing of its blocks (a bit over the demonstrations, a place over their bitset's words);
    a neighbour kept, its exact score (every clause over every demonstration).
    """
    n_g, n = model.n_g, model.n
    n_clauses, n_rows = demos.truth_t.shape
    n_words = max(1, demos.bits.shape[1])
    per_kept = float(max(1, n_clauses) * n_rows)
    return per_kept + n_g * n_rows + n_neighbours_max(n_g, n) * n_words, per_kept


def neighbours_within(rows, demos, model, floor, max_work=np.inf):
    """:func:`weigh_neighbours` row by row, within ``max_work`` (:func:`neighbour_work`).

    Returns ``(neighbours, log_posteriors, sources, done, spent)``: ``sources[i]`` is the
    index in ``rows`` of the row whose neighbour ``neighbours[i]`` is; ``done`` the number of
    rows whose neighbours are all there (the first ``done``: the work is counted after every
    row, and the rows after the one that passed ``max_work`` are left out); ``spent`` the
    work counted. One call's scratch space; :class:`NeighbourWeigher` keeps it for many.
    """
    return NeighbourWeigher(demos, model).within(rows, floor, max_work)


class NeighbourWeigher:
    """:func:`neighbours_within` for one problem, its scratch space allocated once.

    The space is that of a chain's moves and of one hypothesis's neighbours (about 2 ms to
    allocate at 40 activities), so a caller weighing hypotheses one at a time keeps one.
    """

    def __init__(self, demos, model):
        self.demos, self.model = demos, model
        n_cols = state_width(model.n_g, model.n)
        self.per_source, self.per_kept = neighbour_work(demos, model)
        self.bufs = make_buffers(model.n_g, model.n, demos.truth_t.shape[1], 1)
        self.work, self.scratch = _work(demos, model), _scratch(demos, model)
        # one hypothesis's neighbours at a time
        self.out = np.empty((n_neighbours_max(model.n_g, model.n), n_cols), dtype=np.int64)
        self.out_lp = np.empty(self.out.shape[0])

    def one(self, row, floor):
        """The neighbours of one row (int64, contiguous) at or above ``floor``.

        ``(neighbours as int16, log_posteriors, work)``: :meth:`within` of ``row[None, :]``
        without its per-call lists, for a caller weighing states one at a time.
        """
        m, weighed = _weigh(row, self.demos, self.model, float(floor), self.bufs, self.work,
                            self.scratch, self.out, self.out_lp)
        return (self.out[:m].astype(np.int16), self.out_lp[:m].copy(),
                self.per_source + weighed * self.per_kept)

    def within(self, rows, floor, max_work=np.inf):
        """:func:`neighbours_within` of ``rows``."""
        rows = np.ascontiguousarray(rows, dtype=np.int64)
        found, scores, sources = [], [], []
        spent, done = 0.0, 0
        for i in range(rows.shape[0]):
            if spent > max_work:
                break
            near, lps, work = self.one(rows[i], floor)
            found.append(near)
            scores.append(lps)
            sources.append(np.full(len(near), i, dtype=np.int64))
            spent += work
            done += 1
        if not found:
            return (np.empty((0, self.out.shape[1]), dtype=np.int16), np.empty(0),
                    np.empty(0, dtype=np.int64), done, spent)
        return (np.concatenate(found), np.concatenate(scores), np.concatenate(sources), done,
                spent)


@helper
def _keep(out, out_lp, m, row, floor, demos, model, scratch):
    # Score a neighbour weighed near or above the floor from scratch; keep it if it is above.
    lp = _score(row, demos, model, scratch)
    if lp >= floor:
        for c in range(row.shape[0]):
            out[m, c] = row[c]
        out_lp[m] = lp
        m += 1
    return m


@njit(cache=True, nogil=True)
def _weigh(source, demos, model, floor, bufs, work, scratch, out, out_lp):
    n_g, n = model.n_g, model.n
    base, n_cols = parent_offset(n_g, n), state_width(n_g, n)
    w1_at = w1_offset(n_g)
    tau, w1, parent, viol, row = work.tau, work.w1, work.parent, work.viol, work.row
    for j in range(n_g):
        tau[j] = source[j]
    for w in range(n):
        w1[w] = source[w1_at + w]
        parent[w] = source[base + w]
    lp_struct = log_prior_structure(parent, model)
    n_w1 = 0
    for w in range(n):
        n_w1 += w1[w]
    lp_sub = log_prior_globals(tau, model) + log_prior_subset(n_w1, n, model.p_eventual)
    m = np.int64(0)
    scored = np.int64(0)  # neighbours scored from scratch
    if lp_struct + lp_sub == -np.inf:
        return m, scored
    n_conj = fill_viol(viol, tau, w1, parent, demos.truth_t, model)
    cut = floor - MARGIN
    n_gp = n_g - model.pat_in.shape[0]
    k_g = n_plain_globals(tau, model)
    # One inclusion bit: tau's, and W1's too when there is no order to move them with.
    n_bits = n_g + (n if n <= 1 else 0)
    for b in range(n_bits):
        c = b if b < n_g else clause_index_eventual(b - n_g, n_g)
        inc = source[b]
        if b < n_g:
            l_in, l_out = global_inclusion(b, model, k_g - inc if b < n_gp else 0)
        else:
            l_in, l_out = subset_inclusion(n_w1 - inc, n, model.p_eventual)
        ps_out, ns_out, ps_in, ns_in = flip_sums(viol, demos.truth_t, c, inc, demos.w_pos,
                                                 demos.w_neg)
        if inc:  # the neighbour leaves the clause out
            ll = log_likelihood(ps_out, ns_out, demos.n_pos, demos.n_neg, n_conj - 1,
                                model.log_eps, model.likelihood, model.flips)
            lp = lp_struct + lp_sub - l_in + l_out + ll
        else:
            ll = log_likelihood(ps_in, ns_in, demos.n_pos, demos.n_neg, n_conj + 1,
                                model.log_eps, model.likelihood, model.flips)
            lp = lp_struct + lp_sub - l_out + l_in + ll
        if lp >= cut:
            for col in range(n_cols):
                row[col] = source[col]
            row[b] = 1 - inc
            m = _keep(out, out_lp, m, row, floor, demos, model, scratch)
            scored += 1
    if n <= 1:
        return m, scored
    keep_w1, keep_parent, keep_viol = work.keep_w1, work.keep_parent, work.keep_viol
    for w in range(n):
        keep_w1[w] = w1[w]
        keep_parent[w] = parent[w]
    for d in range(viol.shape[0]):
        keep_viol[d] = viol[d]
    forest = is_forest(model)
    for v in range(n):
        # v's place (with F(v)) weighed as its Gibbs move weighs it, at beta = 1: the
        # candidates' weights are the structure's log prior + F(v)'s inclusion + likelihood.
        if forest:
            _, k, _ = forest_candidates(v, parent, w1, viol, n_conj, demos, model, bufs, 1.0)
        else:
            _, k = chain_candidates(v, parent, w1, viol, n_conj, demos, model, bufs, 1.0)
        le = subset_inclusion(n_w1 - keep_w1[v], n, model.p_eventual)
        rest = lp_sub - (le[0] if keep_w1[v] else le[1])
        for i in range(k):
            if rest + bufs.lw[i] < cut:
                continue
            # The candidate's row: the structure without v (parent, now), v put back.
            for col in range(base):
                row[col] = source[col]
            row[w1_at + v] = i & 1
            for u in range(n):
                row[base + u] = parent[u]
            h = bufs.cand_head[i]
            if forest:
                row[base + v] = h
            elif h >= 0:
                # position p of the chain headed by h: after its p-th member, before the rest
                prev = -1
                u = h
                for _ in range(bufs.cand_pos[i]):
                    prev = u
                    u = bufs.child[u]
                nxt = h if prev < 0 else bufs.child[prev]
                row[base + v] = prev
                if nxt >= 0:
                    row[base + nxt] = v
            same = True
            for col in range(n_cols):
                if row[col] != source[col]:
                    same = False
                    break
            if not same:
                m = _keep(out, out_lp, m, row, floor, demos, model, scratch)
                scored += 1
        for w in range(n):
            w1[w] = keep_w1[w]
            parent[w] = keep_parent[w]
        for d in range(viol.shape[0]):
            viol[d] = keep_viol[d]
    return m, scored
