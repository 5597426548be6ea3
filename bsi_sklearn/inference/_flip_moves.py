"""The Gibbs update of one inclusion bit (a ``G``, pattern or eventual clause), two ways.

:func:`flip_move` counts the rows the hypothesis satisfies with and without the clause row by
row (:func:`~bsi_sklearn.inference._gibbs_moves.flip_sums`); :func:`flip_move_masked` counts
them over bitsets of the rows that violate no clause and exactly one (:func:`zero_one_masks`),
in O(words): the sweep's ``G`` and pattern clauses, hundreds with pattern clauses, use it.
Both counts are whole numbers, so both give the same draw, bit for bit. Inlined into the
chain kernel like the moves of :mod:`bsi_sklearn.inference._gibbs_moves`.
"""

import math

import numpy as np
from numba import njit

from bsi_sklearn.inference._gibbs_moves import add_pair, flip_sums, weighted
from bsi_sklearn.model.likelihood import log_likelihood

__all__ = ["flip_move", "flip_move_masked", "zero_one_masks"]


@njit(cache=True, nogil=True, inline="always")
def flip_move(c, inc, lp_in, lp_out, viol, n_conj, demos, model, u, beta):
    """Gibbs update of inclusion bit ``c``: ``(new bit, log-likelihood, uniform used)``."""
    # Gibbs update of one inclusion bit at inverse temperature beta: returns the new bit, the
    # new (untempered) log-likelihood and whether the uniform u was used (only when both
    # outcomes are possible).
    ps_out, ns_out, ps_in, ns_in = flip_sums(viol, demos.truth_t, c, inc, demos.w_pos,
                                             demos.w_neg)
    new, ll, used = _flip_draw(ps_out, ns_out, ps_in, ns_in, inc, lp_in, lp_out, n_conj,
                               demos, model, u, beta)
    if new != inc:
        add_pair(viol, demos.truth_t, c, np.int64(1 if new else -1))
    return new, ll, used


@njit(cache=True, nogil=True, inline="always")
def flip_move_masked(c, inc, lp_in, lp_out, viol, masks, n_conj, demos, model, u, beta):
    """:func:`flip_move` counting over bitsets: the same draw, in O(words) instead of O(rows).

    ``masks[0]`` / ``masks[1]`` are the rows that violate no clause / exactly one
    (:func:`zero_one_masks`), kept up to date here when the bit changes. Without clause ``c``
    a row is satisfied when it violates nothing, or (``c`` included) only ``c``; with it,
    when it violates nothing and ``c`` holds. The counts are whole numbers, as flip_sums's:
    the same sums, the same draw (hundreds of pattern clauses are hundreds of flips a sweep).
    """
    bits, pos, neg = demos.bits, demos.pos_planes, demos.neg_planes
    ps_out, ns_out, ps_in, ns_in = 0, 0, 0, 0
    for w in range(bits.shape[1]):
        z, t = masks[0, w], bits[c, w]
        if inc:
            without, with_c = z | (masks[1, w] & ~t), z
        else:
            without, with_c = z, z & t
        ps_out += weighted(without, pos, w)
        ns_out += weighted(without, neg, w)
        ps_in += weighted(with_c, pos, w)
        ns_in += weighted(with_c, neg, w)
    new, ll, used = _flip_draw(float(ps_out), float(ns_out), float(ps_in), float(ns_in), inc,
                               lp_in, lp_out, n_conj, demos, model, u, beta)
    if new != inc:
        add_pair(viol, demos.truth_t, c, np.int64(1 if new else -1))
        zero_one_masks(viol, masks)
    return new, ll, used


@njit(cache=True, nogil=True, inline="always")
def zero_one_masks(viol, masks):
    """The rows that violate no clause into ``masks[0]``, exactly one into ``masks[1]``."""
    n_rows = viol.shape[0]
    for w in range(masks.shape[1]):
        zero = np.uint64(0)
        one = np.uint64(0)
        base = w << 6
        for b in range(min(64, n_rows - base)):
            zero |= np.uint64(viol[base + b] == 0) << np.uint64(b)
            one |= np.uint64(viol[base + b] == 1) << np.uint64(b)
        masks[0, w] = zero
        masks[1, w] = one


@njit(cache=True, nogil=True, inline="always")
def _flip_draw(ps_out, ns_out, ps_in, ns_in, inc, lp_in, lp_out, n_conj, demos, model, u,
               beta):
    # The new bit, its log-likelihood and whether u was used, from the satisfied counts.
    n_out = n_conj - inc
    ll_out = log_likelihood(ps_out, ns_out, demos.n_pos, demos.n_neg, n_out, model.log_eps,
                            model.likelihood, model.flip_a, model.flip_b)
    ll_in = log_likelihood(ps_in, ns_in, demos.n_pos, demos.n_neg, n_out + 1, model.log_eps,
                           model.likelihood, model.flip_a, model.flip_b)
    lw_out = lp_out + beta * ll_out
    lw_in = lp_in + beta * ll_in
    # P(in) = 1 / (1 + exp(lw_out - lw_in)), computed without overflow.
    used = 0
    if lw_in == -np.inf:
        new = 0
    elif lw_out == -np.inf:
        new = 1
    else:
        diff = lw_out - lw_in
        p_in = 1.0 / (1.0 + math.exp(diff)) if diff < 700.0 else 0.0
        new = 1 if u < p_in else 0
        used = 1
    return new, (ll_in if new else ll_out), used
