"""Everything about the paper's three priors: samplers, closed forms, counts, the support.

This is the one module that knows what each prior is. Its numba functions take the model bundle
(:class:`bsi_sklearn.model.Model`) and are what the exact and MCMC kernels call; the tables in
the bundle (log prior by number of chains, Prior 3's subtree-size terms) are built here, and
the engines ask it what they need of a prior's structures (:func:`is_forest`,
:func:`structures_are_sets`, ...) instead of reading the prior's code. The depth-first walk over
the support lives in :mod:`bsi_sklearn.model._prior_support`, re-exported here.

An order structure is a forest over the subtasks stored as a parent array (``-1`` = root):
Prior 1 (``"linear_chain"``) is a single chain through every subtask, Prior 2
(``"sets_of_chains"``) a set of disjoint chains, Prior 3 (``"forest"``) any forest. The orders
W2 are every ancestor -> descendant pair.
"""

import math

import numpy as np
from numba import njit
from numba.extending import register_jitable

from bsi_sklearn.model._prior_support import (
    FOREST,
    LINEAR_CHAIN,
    enumerate_codes,
    next_assignment,
    next_structure,
)

__all__ = [
    "PRIORS",
    "format_count",
    "prior_code",
    "is_forest",
    "structures_are_sets",
    "first_structure",
    "count_model_hypotheses",
    "whole_structure_log_factor",
    "sample_order_structure",
    "sample_hypothesis",
    "draw_hypothesis",
    "log_prior",
    "log_prior_structure",
    "log_prior_subset",
    "log_prior_globals",
    "global_inclusion",
    "n_plain_globals",
    "log_inclusion",
    "subset_inclusion",
    "LEARNED",
    "prior_tables",
    "count_structures",
    "count_hypotheses",
    "enumerate_structures",
    "next_structure",
    "next_assignment",
    "structure_log_prior",
    "support_structures",
    "n_orders_of",
]

PRIORS = ("linear_chain", "sets_of_chains", "forest")

#: The inclusion probability of a subset's items (``p_global``, ``p_eventual``) as the model
#: bundle holds it where it is learned: unknown, uniform on (0, 1) and integrated out (Scott
#: and Berger 2010), so that a subset of ``k`` of ``n`` items has prior ``1 / ((n + 1) C(n, k))``.
LEARNED = -1.0


def prior_code(prior):
    """Integer code of a prior name (its position in ``PRIORS``), as the model bundle holds it."""
    if prior not in PRIORS:
        raise ValueError(f"unknown prior {prior!r}; expected one of {PRIORS}")
    return PRIORS.index(prior)


# ----------------------------------------------------------------------------- for the engines
# What the exact and MCMC engines need to know of a prior's order structures, asked of the
# model bundle: they never read its prior code.
@register_jitable
def is_forest(model):
    """Whether the model's order structures are any forests, rather than sets of chains.

    Prior 3's trees are moved by pruning and regrafting a subtree; Priors 1 and 2's chains by
    re-inserting one subtask.
    """
    return model.forest


@register_jitable
def structures_are_sets(model):
    """Whether an order structure may be a set of blocks (chains or trees), not just one.

    Under Prior 1 a structure is always one block: one chain through every subtask.
    """
    return model.prior != LINEAR_CHAIN


def first_structure(model):
    """The first order structure of the model's prior, in :func:`next_structure`'s order.

    No orders where the prior allows it; under Prior 1, the chain through the subtasks in
    index order.
    """
    parent = np.full(model.n, -2, dtype=np.int64)
    state = np.zeros(4, dtype=np.int64)
    next_structure(parent, np.zeros(model.n, dtype=np.int64), state, model.prior)
    return parent


def count_model_hypotheses(model):
    """:func:`count_hypotheses` of the model's prior and sizes."""
    return count_hypotheses(PRIORS[model.prior], model.n_g, model.n)


def whole_structure_log_factor(model, n_blocks):
    """The log prior factor of whole structures that a product over their blocks leaves out.

    The exact engine sums a structure's weight over its blocks (:func:`prior_tables`: nothing
    per chain; Prior 3's ``forest_g`` per subtree); what is left depends only on the number of
    blocks: ``lp_chains[n_blocks]`` for chains, ``forest_const`` for forests.

    Parameters
    ----------
    model : Model
    n_blocks : ndarray of int64
        Number of chains (or trees) of every structure.

    Returns
    -------
    ndarray of float64, shaped as ``n_blocks``
    """
    n_blocks = np.asarray(n_blocks, dtype=np.int64)
    if model.forest:
        return np.full(n_blocks.shape, float(model.forest_const))
    return np.asarray(model.lp_chains, dtype=np.float64)[n_blocks]


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
        Probability of starting a new chain after each element (Prior 2); ``LEARNED``: drawn
        uniformly first.
    n_new : float
        Weight of a new tree (Prior 3).

    Returns
    -------
    parent : ndarray of shape (n,), dtype int64
    """
    perm = rng.permutation(n)
    parent = np.full(n, -1, dtype=np.int64)
    p_part = _drawn(p_part, rng)
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
    """Draw ``(tau, w1, parent)`` from the full prior (SampleSubset for both subsets).

    An inclusion probability of ``LEARNED`` (negative) is drawn uniformly first, once for the
    items that share it.
    """
    tau = rng.random(n_globals) < _drawn(p_global, rng)
    w1 = rng.random(n_subtasks) < _drawn(p_eventual, rng)
    parent = sample_order_structure(prior, n_subtasks, rng, p_part, n_new)
    return tau, w1, parent


def _drawn(p, rng):
    # SampleSubset's probability, drawn from its uniform prior where it is learned.
    if np.any(np.asarray(p) < 0):
        return np.where(np.asarray(p) < 0, rng.random(), p)
    return p


def draw_hypothesis(model, rng):
    """Draw ``(tau, w1, parent)`` from the prior a model bundle describes."""
    p_global = model.p_global
    if model.pat_in.shape[0]:  # the pattern slots' own inclusion probabilities
        p_global = np.full(model.n_g, model.p_global)
        p_global[model.n_g - model.pat_in.shape[0]:] = np.exp(model.pat_in)
    return sample_hypothesis(PRIORS[model.prior], model.n_g, model.n, rng, p_global,
                             model.p_eventual, model.p_part, model.n_new)


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
    """log-probability that SampleSubset(n items, p) returns one given subset of size ``k``.

    With ``p = LEARNED``, ``p`` uniform on (0, 1) and integrated out: ``log B(k + 1, n - k +
    1)``, which puts the same mass, ``1 / (n + 1)``, on every size.
    """
    if p < 0.0:
        return math.lgamma(k + 1.0) + math.lgamma(n - k + 1.0) - math.lgamma(n + 2.0)
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
def log_inclusion(p):
    """``(log p, log(1 - p))``: the log prior of including / leaving out one clause."""
    lin = math.log(p) if p > 0 else -np.inf
    lout = math.log1p(-p) if p < 1 else -np.inf
    return lin, lout


@register_jitable
def subset_inclusion(k_others, n, p):
    """Log prior weights of including / leaving out one of ``n`` items.

    ``k_others`` of the others are in. The two weights differ by the change of
    :func:`log_prior_subset` from the subset without the item to the subset with it. A fixed
    ``p`` gives :func:`log_inclusion`'s, whatever the others; a learned one (``LEARNED``)
    ``(log(k_others + 1), log(n - k_others))``: the more items in, the likelier one more.

    Examples
    --------
    >>> import math
    >>> k, n = 2, 5
    >>> lin, lout = subset_inclusion(k, n, LEARNED)
    >>> math.isclose(lin - lout, log_prior_subset(k + 1, n, LEARNED)
    ...              - log_prior_subset(k, n, LEARNED))
    True
    """
    if p < 0.0:
        return math.log(k_others + 1.0), math.log(float(n - k_others))
    return log_inclusion(p)


@njit(cache=True, nogil=True)
def _log_prior_chains(n, m, code, p_part):
    # Priors 1 and 2 depend on a chain structure only through its number of chains m.
    if code == LINEAR_CHAIN:
        if m != 1:
            return -np.inf
        return -math.lgamma(n + 1.0)
    # The chains are the cuts among the n - 1 places between the permutation's elements: a
    # subset of them, with probability p_part each (or learned, integrated out).
    return (math.lgamma(m + 1.0) - math.lgamma(n + 1.0)
            + log_prior_subset(m - 1, n - 1, p_part))


@njit(cache=True, nogil=True)
def _log_prior_forest(parent, n_children, n_roots, n_new):
    n = parent.shape[0]
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
def _count_children(parent, n_children):
    # Number of children of every node, into n_children; returns the number of roots.
    n_children[:] = 0
    n_roots = 0
    for v in range(parent.shape[0]):
        if parent[v] < 0:
            n_roots += 1
        else:
            n_children[parent[v]] += 1
    return n_roots


@njit(cache=True, nogil=True)
def log_prior_structure(parent, model):
    """Closed-form log-probability of an order structure under the model's prior.

    Parameters
    ----------
    parent : ndarray of int64
        Parent of every subtask (-1 for a root). Must be a forest.
    model : Model
        The bundle of :func:`bsi_sklearn.model.make_model`; its prior, ``p_part`` and
        ``n_new`` are read.

    Returns
    -------
    float
        ``-inf`` outside the prior's support.
    """
    n = parent.shape[0]
    if n == 0:
        return 0.0
    n_children = np.zeros(n, dtype=np.int64)
    n_roots = _count_children(parent, n_children)
    if model.prior == FOREST:
        return _log_prior_forest(parent, n_children, n_roots, model.n_new)
    for v in range(n):
        if n_children[v] > 1:
            return -np.inf
    return _log_prior_chains(n, n_roots, model.prior, model.p_part)


@register_jitable
def log_prior_globals(tau, model):
    """Log prior of the global slots of a hypothesis: its ``G`` clauses, its pattern clauses.

    The ``G`` clauses are SampleSubset(|T|, p_global) (the paper's term, computed as it
    always was); each pattern clause, the last ``len(model.pat_in)`` slots, is an independent
    inclusion with its own probability (DESIGN §12).
    """
    n_pat = model.pat_in.shape[0]
    n_gp = tau.shape[0] - n_pat
    lp = log_prior_subset(n_plain_globals(tau, model), n_gp, model.p_global)
    for i in range(n_pat):
        lp += model.pat_in[i] if tau[n_gp + i] else model.pat_out[i]
    return lp


@register_jitable
def global_inclusion(j, model, k_others):
    """Log prior weights of including / leaving out global slot ``j``.

    A ``G`` slot's by :func:`subset_inclusion` (``k_others``: the other ``G`` slots included),
    a pattern slot's its own.
    """
    n_gp = model.n_g - model.pat_in.shape[0]
    if j < n_gp:
        return subset_inclusion(k_others, n_gp, model.p_global)
    return model.pat_in[j - n_gp], model.pat_out[j - n_gp]


@register_jitable
def n_plain_globals(tau, model):
    """How many of the ``G`` slots (not the pattern slots) ``tau`` includes."""
    k = 0
    for j in range(model.n_g - model.pat_in.shape[0]):
        k += tau[j]
    return k


@njit(cache=True, nogil=True)
def log_prior(tau, w1, parent, model):
    """Log prior of a whole hypothesis: both subsets (SampleSubset) and the order structure."""
    return (log_prior_globals(tau, model)
            + log_prior_subset(w1.sum(), w1.shape[0], model.p_eventual)
            + log_prior_structure(parent, model))


def _forest_size_terms(n, n_new):
    """Prior 3 as a sum over subtree sizes.

    Every subtask v with subtree size s_v enters the forest prior through lgamma(s_v) (its
    block in its parent's, or the top-level, CRP partition), -log(s_v) (its root is its
    first element) and, when s_v > 1, the CRP normaliser lgamma(theta) - lgamma(theta + s_v
    - 1) of its descendants' partition. The per-block log(theta) terms add up to
    n log(theta) (every subtask is a root or one parent's child). So
    ``log p = const + sum_v g[s_v]``; returns ``(g, const)``.
    """
    log_theta = math.log(n_new)
    lg0 = math.lgamma(n_new)
    g = np.zeros(n + 2)
    for k in range(1, n + 1):
        g[k] = math.lgamma(float(k)) - math.log(float(k))
        if k > 1:
            g[k] += lg0 - math.lgamma(n_new + k - 1)
    return g, n * log_theta + lg0 - math.lgamma(n_new + n)


def prior_tables(prior, n, p_part, n_new):
    """What the MCMC moves need of a prior, tabulated once per fit.

    Returns
    -------
    forest : bool
        Whether structures are forests (Prior 3: prune-and-regraft moves) rather than sets of
        chains (Priors 1, 2: re-insertion moves).
    lp_chains : ndarray of shape (n + 2,)
        Log prior of a chain structure with ``m`` chains (Priors 1, 2; ``-inf`` where the
        prior has no such structure, e.g. a second chain under Prior 1).
    forest_g, forest_const : ndarray of shape (n + 2,), float
        Prior 3 as ``const + sum_v g[subtree size of v]``.
    """
    code = prior_code(prior)
    lp_chains = np.array([_log_prior_chains(n, m, code, p_part) if 1 <= m <= n else -np.inf
                          for m in range(n + 2)], dtype=np.float64)
    g, g_const = _forest_size_terms(n, n_new)
    return code == FOREST, lp_chains, g, float(g_const)


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


def count_hypotheses(prior, n_globals, n_subtasks):
    """Number of hypotheses in the prior's support (structures x global x eventual subsets).

    Examples
    --------
    >>> count_hypotheses("sets_of_chains", 5, 5)
    513024
    """
    return count_structures(prior, n_subtasks) * 2**n_globals * 2**n_subtasks


def format_count(count):
    """A count of hypotheses for a message: three digits, also beyond a float's range.

    Examples
    --------
    >>> format_count(513024), format_count(10**400 * 3)
    ('5.13e+05', '3.00e+400')
    """
    count = int(count)
    if count < 10**300:
        return f"{float(count):.3g}"
    digits = str(count)
    return f"{digits[0]}.{digits[1:3]}e+{len(digits) - 1}"


@njit(cache=True, nogil=True)
def structure_log_prior(parent, model, scratch):
    """``log_prior_structure`` for a structure known to be in the support, without allocating.

    ``scratch`` is an int64 array of ``len(parent)`` elements. Uses the tables of the model
    bundle (chains: by number of chains; forests: by subtree sizes).
    """
    n = parent.shape[0]
    if not model.forest:
        m = 0
        for v in range(n):
            if parent[v] < 0:
                m += 1
        return model.lp_chains[m] if n else 0.0
    for v in range(n):
        scratch[v] = 1
    for v in range(n):
        a = parent[v]
        while a >= 0:
            scratch[a] += 1
            a = parent[a]
    out = model.forest_const
    for v in range(n):
        out += model.forest_g[scratch[v]]
    return out


def enumerate_structures(prior, n):
    """All order structures (parent arrays) of a prior's support, shape ``(count, n)``.

    Examples
    --------
    >>> enumerate_structures("sets_of_chains", 2)
    array([[-1, -1],
           [-1,  0],
           [ 1, -1]])
    """
    return enumerate_codes(n, prior_code(prior), count_structures(prior, n))


def support_structures(model):
    """Every order structure of the model's prior, over its ``model.n`` subtasks."""
    return enumerate_structures(PRIORS[model.prior], model.n)
