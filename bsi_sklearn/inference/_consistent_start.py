"""A second start for the deterministic optimum: every clause the acceptable demonstrations keep.

Under the size principle (CB, the paper's likelihood) a clause that every acceptable demonstration
satisfies earns ``log 2`` per acceptable demonstration, and one that any of them violates costs
``|log eps|``: the optimum keeps every clause the acceptable demonstrations keep, and arranges
the orders among them in the structure with the most ancestor -> descendant pairs. The beam
search from the hypothesis without clauses reaches it one block at a time, and on event logs of
dozens of activities it stops short: adding a subtask to the middle of a chain, or moving a
chain under another, is several blocks, each worse than the last (40 activities, 200 cases:
420 nats below the optimum, which the chains then took 10,000 sweeps to climb to).

:func:`consistent_start` builds that hypothesis directly. The orders the acceptable
demonstrations keep form a relation that is transitive where the clauses have no conditions
(``(!b U a)`` and ``(!c U b)`` imply ``(!c U a)`` on every trace), so a chain (or a tree path)
whose every ancestor precedes every descendant in it is a path in that relation; the chains are
the longest such paths, taken greedily (Priors 1 and 2), the trees give every subtask the
deepest admissible parent (Prior 3). It is only a start: the beam search scores every
hypothesis exactly and keeps what the posterior says, whichever likelihood it is. No random
numbers.
"""

import numpy as np

from bsi_sklearn.model.clauses import clause_index_eventual, clause_index_order
from bsi_sklearn.model.priors import is_forest, structures_are_sets
from bsi_sklearn.model.state_layout import join_state

__all__ = ["consistent_start"]


def consistent_start(demos, model):
    """The hypothesis of every clause that every acceptable demonstration satisfies.

    Parameters
    ----------
    demos : Demos
        Deduplicated clause truth (:func:`bsi_sklearn.inference.mcmc.deduplicate_demos`).
    model : Model

    Returns
    -------
    ndarray of int64
        A row ``[tau, w1, parent]`` (:mod:`bsi_sklearn.model.state_layout`) in the prior's
        support: every global and eventual clause kept by every acceptable demonstration, and
        an order structure of orders they all keep (without acceptable demonstrations, every
        clause and every order is kept).
    """
    n_g, n = model.n_g, model.n
    # A reduction over the acceptable columns in place: no copy of the clause truth, which is
    # the fit's largest array (clauses x unique demonstrations).
    kept = np.min(demos.truth_t, axis=1, where=(demos.w_pos > 0)[None, :], initial=1) > 0
    tau = kept[np.arange(n_g)]  # G(tau_j) is clause slot j
    w1 = kept[[clause_index_eventual(w, n_g) for w in range(n)]]
    before = np.zeros((n, n), dtype=bool)  # before[a, b]: every acceptable one keeps a < b
    for a in range(n):
        before[a] = kept[[clause_index_order(a, b, n_g, n) for b in range(n)]]
    np.fill_diagonal(before, False)
    return join_state(tau, w1, _structure(before, is_forest(model),
                                          structures_are_sets(model)))


def _structure(before, forest, sets):
    # Parents of an order structure of the prior whose every ancestor -> descendant pair is
    # in `before`. A subtask with more successors comes first (in a transitive relation a
    # predecessor has strictly more), so following `rank` never closes a cycle, even where
    # conditions break transitivity or two subtasks keep each other's order.
    n = before.shape[0]
    order = np.lexsort((np.arange(n), -before.sum(axis=1)))
    parent = np.full(n, -1, dtype=np.int64)
    if not sets:  # Prior 1, one chain through every subtask: the rank's order
        parent[order[1:]] = order[:-1]
        return parent
    rank = np.empty(n, dtype=np.int64)
    rank[order] = np.arange(n)
    before = before & (rank[:, None] < rank[None, :])
    if forest:
        _deepest_parents(before, order, parent, np.ones(n, dtype=bool))
        return parent
    free = np.ones(n, dtype=bool)
    while free.any():  # sets of chains: the longest chain of what is left, until none is left
        prev = np.full(n, -1, dtype=np.int64)
        depth = _deepest_parents(before, order, prev, free)
        end = int(np.argmax(np.where(free, depth, -1)))
        if depth[end] == 0:
            break
        while end >= 0:
            free[end] = False
            parent[end] = prev[end]
            end = prev[end]
    return parent


def _deepest_parents(before, order, parent, free):
    # Every free subtask, in rank order, under the deepest free subtask whose path from its
    # root (itself included) precedes it entirely; the depths.
    n = before.shape[0]
    depth = np.zeros(n, dtype=np.int64)
    path = np.zeros((n, n), dtype=bool)  # path[u]: u and its ancestors
    for v in order:
        if not free[v]:
            continue
        cand = np.flatnonzero(free & before[:, v])
        cand = cand[~(path[cand] & ~before[:, v]).any(axis=1)]
        if len(cand):
            u = int(cand[np.argmax(depth[cand])])
            parent[v], depth[v] = u, depth[u] + 1
            path[v] = path[u]
        path[v, v] = True
    return depth
