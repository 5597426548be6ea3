"""The depth-first walk over a prior's support of order structures (private to priors.py).

:mod:`bsi_sklearn.model.priors` is the interface: it re-exports :func:`next_assignment` and
:func:`next_structure` and enumerates whole supports with them; the walk lives here so that
each module keeps one job (the closed forms and tables there, the walk here). The prior codes
are the positions of the prior names in ``priors.PRIORS``.
"""

import numpy as np
from numba import njit

__all__ = ["LINEAR_CHAIN", "SETS_OF_CHAINS", "FOREST", "next_assignment", "next_structure",
           "enumerate_codes"]

LINEAR_CHAIN, SETS_OF_CHAINS, FOREST = 0, 1, 2  # codes: positions in priors.PRIORS


@njit(cache=True, nogil=True)
def next_assignment(parent, n_children, state, code, descend):
    """One depth-first step over the order structures of the prior's support.

    Nodes get their parents in index order; the call makes the next assignment and returns
    the node it assigned (a whole structure is in ``parent`` when that is the last node), or
    -1 when every structure has been visited. With ``descend`` False the nodes after the last
    assignment are not tried (its subtree is skipped). Start with ``parent`` filled with
    ``-2``, ``n_children`` with 0 and ``state = [0, 0, 0, 0]`` (level, roots, done, started);
    ``n`` must be at least 1. Only valid partial structures are visited: a node's parent is
    never its descendant, nor (Priors 1, 2) a node that already has a child, nor (Prior 1) a
    second root. Structures come in lexicographic order of their parent arrays.
    """
    n = parent.shape[0]
    if state[2]:
        return -1
    v = state[0]
    roots = state[1]
    if state[3] and descend and v < n - 1:
        v += 1
    state[3] = 1
    while v >= 0:
        u = parent[v]
        if u >= 0:
            n_children[u] -= 1
        elif u == -1:
            roots -= 1
        u += 1
        while u < n:
            if u == -1:
                if code != LINEAR_CHAIN or roots == 0:
                    break
            elif u != v and (code == FOREST or n_children[u] == 0):
                a = u  # u must not descend from v among the nodes placed so far
                while 0 <= a < v:
                    a = parent[a]
                if a != v:
                    break
            u += 1
        if u == n:
            parent[v] = -2
            v -= 1
            continue
        parent[v] = u
        if u >= 0:
            n_children[u] += 1
        else:
            roots += 1
        state[0] = v
        state[1] = roots
        return v
    state[2] = 1
    return -1


@njit(cache=True, nogil=True)
def next_structure(parent, n_children, state, code):
    """Advance ``parent`` to the next order structure of the prior's support (depth-first).

    Same start as :func:`next_assignment`; each call that returns True leaves the next
    structure in ``parent`` (for ``n = 0``, the empty structure once).
    """
    n = parent.shape[0]
    if n == 0:
        done = state[2] == 1
        state[2] = 1
        return not done
    while True:
        v = next_assignment(parent, n_children, state, code, True)
        if v < 0:
            return False
        if v == n - 1:
            return True


@njit(cache=True)
def enumerate_codes(n, code, count):
    """Every structure over ``n`` subtasks of the prior of code ``code``, as parent arrays.

    ``count`` is the support's size (``priors.count_structures``), the number of rows.
    """
    out = np.empty((count, n), dtype=np.int64)
    parent = np.full(n, -2, dtype=np.int64)
    n_children = np.zeros(n, dtype=np.int64)
    state = np.zeros(4, dtype=np.int64)
    k = 0
    while next_structure(parent, n_children, state, code):
        out[k] = parent
        k += 1
    return out
