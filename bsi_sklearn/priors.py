"""The paper's three priors: program-following samplers and closed-form log-probabilities.

An order structure is a forest over the subtasks stored as a parent array (``-1`` = root):
Prior 1 (``"linear_chain"``) is a single chain through every subtask, Prior 2
(``"sets_of_chains"``) a set of disjoint chains, Prior 3 (``"forest"``) any forest. The orders
W2 are every ancestor -> descendant pair.
"""

import math

import numpy as np
from numba import njit

__all__ = [
    "PRIORS",
    "prior_code",
    "sample_order_structure",
    "sample_hypothesis",
    "log_prior_structure",
    "log_prior_subset",
    "count_structures",
    "orders_of",
]

PRIORS = ("linear_chain", "sets_of_chains", "forest")
_PRIOR_CODE = {"linear_chain": 0, "sets_of_chains": 1, "forest": 2}


def prior_code(prior):
    """Integer code of a prior name for the kernels."""
    return _PRIOR_CODE[prior]


# ----------------------------------------------------------------------------- samplers
def sample_order_structure(prior, n, rng, p_part=0.3, n_new=5.0):
    """Draw an order structure from a prior by running the paper's probabilistic program.

    Parameters
    ----------
    prior : {"linear_chain", "sets_of_chains", "forest"}
    n : int
        Number of subtasks.
    rng : numpy.random.Generator
    p_part : float
        Probability of starting a new chain after each element (Prior 2).
    n_new : float
        Weight of a new tree (Prior 3).

    Returns
    -------
    parent : ndarray of shape (n,), dtype int64
    """
    perm = rng.permutation(n)
    parent = np.full(n, -1, dtype=np.int64)
    if prior == "linear_chain":
        for i in range(1, n):
            parent[perm[i]] = perm[i - 1]
    elif prior == "sets_of_chains":
        # Algorithm SampleSetsOfLinearChains: append to the active chain, then maybe cut.
        last = -1
        for a in perm:
            parent[a] = last
            last = -1 if rng.random() < p_part else a
    elif prior == "forest":
        # Algorithm SampleForestofSubtasks: CRP-like recursive insertion.
        children = {-1: []}  # node -> list of child roots (the node's descendant forest)
        size = {}
        for a in perm:
            node = -1
            while True:
                forest = children[node]
                weights = np.array([size[r] for r in forest] + [n_new], dtype=float)
                i = rng.choice(len(weights), p=weights / weights.sum())
                if i == len(forest):
                    forest.append(a)
                    parent[a] = node
                    children[a], size[a] = [], 1
                    break
                node = forest[i]
                size[node] += 1
    else:
        raise ValueError(f"unknown prior {prior!r}; expected one of {PRIORS}")
    return parent


def sample_hypothesis(prior, n_globals, n_subtasks, rng, p_global=0.8, p_eventual=0.8,
                      p_part=0.3, n_new=5.0):
    """Draw ``(tau, w1, parent)`` from the full prior (SampleSubset for both subsets)."""
    tau = rng.random(n_globals) < p_global
    w1 = rng.random(n_subtasks) < p_eventual
    parent = sample_order_structure(prior, n_subtasks, rng, p_part, n_new)
    return tau, w1, parent


# ----------------------------------------------------------------------------- closed forms
@njit(cache=True, nogil=True)
def _xlog(k, p):
    # k * log(p) with 0 * log(0) = 0.
    if k == 0:
        return 0.0
    if p <= 0.0:
        return -np.inf
    return k * math.log(p)


@njit(cache=True, nogil=True)
def log_prior_subset(k, n, p):
    """log-probability that SampleSubset(n items, p) returns one given subset of size ``k``."""
    return _xlog(k, p) + _xlog(n - k, 1.0 - p)


@njit(cache=True, nogil=True)
def _subtree_sizes(parent):
    n = parent.shape[0]
    size = np.ones(n, dtype=np.int64)
    for v in range(n):
        a = parent[v]
        while a >= 0:
            size[a] += 1
            a = parent[a]
    return size


@njit(cache=True, nogil=True)
def _log_crp(block_sizes_sum_lgamma, k, m, theta):
    # EPPF of a CRP(theta) partition of m items into k blocks.
    if m == 0:
        return 0.0
    return k * math.log(theta) + math.lgamma(theta) - math.lgamma(theta + m) + \
        block_sizes_sum_lgamma


@njit(cache=True, nogil=True)
def log_prior_structure(parent, code, p_part, n_new):
    """Closed-form log-probability of an order structure under a prior (``-inf`` outside it).

    Parameters
    ----------
    parent : ndarray of int64
        Parent of every subtask (-1 for a root). Must be a forest.
    code : int
        0 linear chain (Prior 1), 1 sets of chains (Prior 2), 2 forest (Prior 3).
    p_part, n_new : float
    """
    n = parent.shape[0]
    if n == 0:
        return 0.0
    n_children = np.zeros(n, dtype=np.int64)
    n_roots = 0
    for v in range(n):
        if parent[v] < 0:
            n_roots += 1
        else:
            n_children[parent[v]] += 1
    if code <= 1:
        for v in range(n):
            if n_children[v] > 1:
                return -np.inf
        if code == 0:
            if n_roots != 1:
                return -np.inf
            return -math.lgamma(n + 1.0)
        m = n_roots
        return (math.lgamma(m + 1.0) - math.lgamma(n + 1.0)
                + _xlog(m - 1, p_part) + _xlog(n - m, 1.0 - p_part))
    size = _subtree_sizes(parent)
    # Top level: partition of all n subtasks into the root trees.
    acc = 0.0
    for v in range(n):
        if parent[v] < 0:
            acc += math.lgamma(float(size[v]))
    out = _log_crp(acc, n_roots, n, n_new)
    # Each node's descendant forest: partition of size-1 subtasks into the child trees.
    child_acc = np.zeros(n)
    for v in range(n):
        if parent[v] >= 0:
            child_acc[parent[v]] += math.lgamma(float(size[v]))
    for v in range(n):
        out += _log_crp(child_acc[v], n_children[v], size[v] - 1, n_new)
        out -= math.log(float(size[v]))  # the tree's root is its first element
    return out


@njit(cache=True, nogil=True)
def n_orders_of(parent):
    """``|W2|``: the number of ancestor -> descendant pairs."""
    total = 0
    for v in range(parent.shape[0]):
        a = parent[v]
        while a >= 0:
            total += 1
            a = parent[a]
    return total


def orders_of(parent):
    """Ancestor -> descendant pairs ``(a, b)`` (indices into the subtasks)."""
    pairs = []
    for v in range(len(parent)):
        a = parent[v]
        while a >= 0:
            pairs.append((int(a), int(v)))
            a = parent[a]
    return pairs


def count_structures(prior, n):
    """Size of the prior's support over order structures for ``n`` subtasks.

    Examples
    --------
    >>> [count_structures("sets_of_chains", n) for n in range(6)]
    [1, 1, 3, 13, 73, 501]
    >>> count_structures("forest", 5), count_structures("linear_chain", 5)
    (1296, 120)
    """
    if prior == "linear_chain":
        return math.factorial(n)
    if prior == "sets_of_chains":
        # Sets of lists (OEIS A000262): a(n) = (2n-1) a(n-1) - (n-1)(n-2) a(n-2).
        a = [1, 1]
        for k in range(2, n + 1):
            a.append((2 * k - 1) * a[k - 1] - (k - 1) * (k - 2) * a[k - 2])
        return a[n]
    if prior == "forest":
        return (n + 1) ** (n - 1) if n > 0 else 1
    raise ValueError(f"unknown prior {prior!r}; expected one of {PRIORS}")
