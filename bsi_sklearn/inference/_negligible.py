"""Samples that provably carry no posterior mass: a chain stuck far below what the others found.

The support holds at most ``S = 2^(n_g + n) (n + 1)^n`` hypotheses (an inclusion bit per
global or pattern clause and per eventual clause, a parent or none per subtask: every prior's
structures are such parent arrays). If the best state the chains found has log posterior
``L*``, every state of log posterior below ``L* - log S - log(1 / TOL)`` together holds less
than ``S exp(-log S - log(1 / TOL)) = TOL`` of the posterior mass, whatever the posterior:
the normaliser is at least ``exp(L*)``. A chain whose recorded samples all lie there samples a
region that does not exist at double precision; its sample frequencies would count it as if
it did.

This happens where modes are separated by misclassified demonstrations, each costing
``|log eps|`` (thousands of nats on an event log with hundreds of candidate clauses): on a
Declare log of 40 activities with pattern clauses under the calibrated likelihood, three chains
of four left the deterministic optimum's mode for one 6,671 nats higher and the fourth never
did; its samples made the chains disagree for 10,000 sweeps (a bound of 1,314 nats there).

So the samples before the last chain to reach the region within the bound does are burn-in,
for every chain alike (their traces stay of equal length for split-R-hat); a chain that reaches
it only in the second half of its samples, or never, is left out. A peaked posterior, whose
chains start at the deterministic optimum and burn in near it, never meets the bound: nothing
changes there.
"""

import math

import numpy as np

__all__ = ["NEGLIGIBLE_MASS", "negligible_margin", "common_burn_in"]

#: Posterior mass the samples left out may carry at most: the exact engine's bound
#: (``inference/exact.py``) for what it skips.
NEGLIGIBLE_MASS = 1e-17


def negligible_margin(n_g, n, tol=NEGLIGIBLE_MASS):
    """``log S + log(1 / tol)`` for the support's size bound ``S = 2^(n_g + n) (n + 1)^n``.

    Examples
    --------
    >>> round(negligible_margin(0, 0), 2)  # one hypothesis: log(1e17)
    39.14
    >>> round(negligible_margin(2, 1) - negligible_margin(0, 0), 4)  # 2^3 * 2^1 = 16
    2.7726
    """
    return (n_g + n) * math.log(2.0) + n * math.log(n + 1.0) + math.log(1.0 / tol)


def common_burn_in(chain_rows, chain_counts, visited_lp, margin):
    """Samples every chain discards, and which chains remain, by the bound above.

    Parameters
    ----------
    chain_rows, chain_counts : sequence of ndarray of int
        For each chain, the index into ``visited_lp`` of each row of its run-length encoded
        record, and the samples the row stands for.
    visited_lp : ndarray of float
        Exact log posterior of every visited state.
    margin : float
        :func:`negligible_margin`.

    Returns
    -------
    skip : int
        Samples to discard from the start of every remaining chain: the latest first sample
        within ``margin`` of the best visited state among them (0 where every chain starts
        there).
    live : ndarray of bool
        The chains that reach the region in the first half of their samples.

    Examples
    --------
    Two chains of 10 samples; the second starts 5,000 nats below the best and climbs after
    2 samples; a third never climbs:

    >>> import numpy as np
    >>> lp = np.array([0.0, -5000.0])
    >>> rows = [np.array([0]), np.array([1, 0]), np.array([1])]
    >>> counts = [np.array([10]), np.array([2, 8]), np.array([10])]
    >>> skip, live = common_burn_in(rows, counts, lp, margin=100.0)
    >>> int(skip), live.tolist()
    (2, [True, True, False])
    """
    best = max(float(visited_lp[rows].max()) for rows in chain_rows if len(rows))
    floor = best - margin
    first = []
    for rows, counts in zip(chain_rows, chain_counts):
        counts = np.asarray(counts, dtype=np.int64)
        good = np.flatnonzero(visited_lp[rows] >= floor)
        first.append(int(np.sum(counts[:good[0]])) if len(good) else int(np.sum(counts)))
    first = np.asarray(first)
    total = np.array([int(np.sum(c)) for c in chain_counts])
    live = first <= total // 2
    if not live.any():  # only late climbers: the chain holding the best state reached it
        live = first < total
    return int(first[live].max()), live
