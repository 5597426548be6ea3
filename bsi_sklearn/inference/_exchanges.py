"""Exchange neighbours: two subtasks trade places in the order structure.

On an event log with few cases for many activities the posterior's top is a plateau of
specifications of exactly the same probability: activity ``a20`` may be followed by any of
``a31``, ``a34``, ``a36`` or ``a38`` in a chain, the others left alone, and so on for every
such choice (``make_process_log(40, 286, random_state=0)``, 200 training cases: about 11,000
specifications). Two of them are two Gibbs blocks apart (take ``a38`` out of the chain, put
``a36`` in) across a valley of one order's worth of evidence (75 nats under the size
principle), so neither a single move nor the one-block closure joins them
(:mod:`bsi_sklearn.inference._closure`), and the tempered chains took about 8,000 sweeps to
list them. Exchanging the two subtasks' places is one step between them, of no cost.

:func:`exchange_neighbours` lists, for one hypothesis, every hypothesis that exchanges two
subtasks' places (each takes the other's parent and children; the eventual bits stay with the
subtasks), and keeps those at or above a floor. The violation counts change only through the
orders that involve one of the two, which are taken out and put back; the counts being whole
numbers, the neighbour's log posterior is the one :func:`~._rounds.score_states` computes, to the
bit, without a pass over every conjunct. No random numbers.
"""

import math

import numpy as np
from numba import njit

from bsi_sklearn._unique_rows import row_keys
from bsi_sklearn.inference._chain_kernel import fill_viol
from bsi_sklearn.inference._gibbs_moves import add_pair
from bsi_sklearn.inference._row_counts import sat_counts
from bsi_sklearn.model.clauses import clause_index_order
from bsi_sklearn.model.likelihood import log_likelihood
from bsi_sklearn.model.priors import log_prior
from bsi_sklearn.model.state_layout import parent_offset, split_state, state_width

__all__ = ["exchange_neighbours", "n_exchanges", "ExchangeWeigher"]


def n_exchanges(n):
    """Exchange neighbours a hypothesis has at most: one per pair of subtasks."""
    return math.comb(n, 2)


class ExchangeWeigher:
    """:func:`exchange_neighbours` for one problem, its scratch space allocated once."""

    def __init__(self, demos, model):
        self.demos, self.model = demos, model
        n, d = model.n, demos.truth_t.shape[1]
        self.viol = np.zeros((2, d), dtype=np.int32)
        self.parents = np.empty((2, n), dtype=np.int64)  # the row's and the exchanged
        n_cols = state_width(model.n_g, n)
        self.out = np.empty((max(1, n_exchanges(n)), n_cols), dtype=np.int64)
        self.out_lp = np.empty(self.out.shape[0])

    def within(self, row, floor):
        """``(neighbours int16, log posteriors, work)`` of one row (:func:`exchange_neighbours`).

        ``work`` counts clause-row operations, as :mod:`._neighbour_weights` does.
        """
        m, work = _exchanges(np.ascontiguousarray(row, dtype=np.int64), self.demos,
                             self.model, float(floor), self.viol, self.parents, self.out,
                             self.out_lp)
        # Two exchanges give the same row where the structure has a symmetry (two chains of
        # two: a <-> c and b <-> d): keep the first of each. A set of the rows' bytes: a few
        # dozen rows per call, where a sort's fixed cost would dominate.
        rows = self.out[:m].astype(np.int16)
        first, seen = [], set()
        for i, key in enumerate(row_keys(rows)):
            if key not in seen:
                seen.add(key)
                first.append(i)
        return rows[first], self.out_lp[first], float(work)


def exchange_neighbours(row, demos, model, floor):
    """Every exchange of two subtasks' places in ``row`` scoring at least ``floor``.

    Parameters
    ----------
    row : ndarray of int
        A hypothesis ``[tau, w1, parent]`` (:mod:`bsi_sklearn.model.state_layout`).
    demos : Demos
    model : Model
    floor : float

    Returns
    -------
    neighbours : ndarray of shape (m, n_cols), int16
        Distinct rows, none equal to ``row``.
    log_posteriors : ndarray of shape (m,)
        Their exact log posteriors (as :func:`bsi_sklearn.inference._rounds.score_states`).
    """
    found, lps, _ = ExchangeWeigher(demos, model).within(row, floor)
    return found, lps


@njit(cache=True, nogil=True)
def _orders_of(viol, parent, x, y, sign, truth_t, n_g):
    # Add `sign` to the violation counts for every order of `parent` (ancestor -> descendant)
    # that involves x or y; the number of such orders and the steps walked.
    n = parent.shape[0]
    k = np.int64(0)
    steps = np.int64(0)
    for v in range(n):
        a = parent[v]
        while a >= 0:
            steps += 1
            if v == x or v == y or a == x or a == y:
                add_pair(viol, truth_t, clause_index_order(a, v, n_g, n), sign)
                k += 1
            a = parent[a]
    return k, steps


@njit(cache=True, nogil=True)
def _exchanges(source, demos, model, floor, viol, parents, out, out_lp):
    n_g, n = model.n_g, model.n
    base = parent_offset(n_g, n)
    d = viol.shape[1]
    tau, w1, parent = split_state(source, n_g, n)
    tau, w1 = tau.copy(), w1.copy()
    old, new = parents[0], parents[1]
    for v in range(n):
        old[v] = parent[v]
    m = np.int64(0)
    work = np.int64(0)
    if n < 2:
        return m, work
    lp_prior = log_prior(tau, w1, old, model)
    if lp_prior == -np.inf:
        return m, work
    n_conj = fill_viol(viol[0], tau, w1, old, demos.truth_t, model)
    for x in range(n):
        for y in range(x + 1, n):
            # y takes x's place and x takes y's: relabel the structure by the exchange.
            same = True
            for v in range(n):
                p = old[v]
                p = y if p == x else (x if p == y else p)
                u = y if v == x else (x if v == y else v)
                new[u] = p
            for v in range(n):
                if new[v] != old[v]:
                    same = False
                    break
            if same:
                continue
            for r in range(d):
                viol[1, r] = viol[0, r]
            k_out, s_out = _orders_of(viol[1], old, x, y, -1, demos.truth_t, n_g)
            k_in, s_in = _orders_of(viol[1], new, x, y, 1, demos.truth_t, n_g)
            work += d + s_out + s_in + (k_out + k_in) * d
            # The violation counts are whole numbers and the satisfied sums sums of whole
            # numbers, exact in any order: the likelihood gets the arguments _score would
            # give it, and the prior is log_prior of the exchanged structure, so the log
            # posterior is score_states' to the bit without a pass over every conjunct.
            ps, ns = sat_counts(viol[1], demos.w_pos, demos.w_neg)
            lp = log_prior(tau, w1, new, model) + log_likelihood(
                ps, ns, demos.n_pos, demos.n_neg, n_conj - k_out + k_in, model.log_eps,
                model.likelihood, model.flips)
            if lp >= floor:
                for c in range(base):
                    out[m, c] = source[c]
                for v in range(n):
                    out[m, base + v] = new[v]
                out_lp[m] = lp
                m += 1
    return m, work
