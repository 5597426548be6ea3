"""Weighted counts of the demonstrations a hypothesis satisfies: row by row, and as bitsets.

Every likelihood is a function of two such counts (the acceptable and the unacceptable
demonstrations satisfied, ``docs/likelihoods.md``). The chains keep, for every unique row,
the number of the hypothesis's clauses it violates (``viol``); a row counts when that number
is 0. The bitset forms read the packed truth (``Demos.bits``) and the weights' bit-planes
(``Demos.pos_planes`` / ``neg_planes``): a weighted count is a sum of popcounts. The weights
are whole numbers, so every form gives the same floats as the row-by-row sums.
"""

import numpy as np
from numba import njit

from bsi_sklearn.model.clauses import popcount

__all__ = ["sat_counts", "flip_sums", "zero_mask", "weighted_popcount", "bit_sums",
           "flip_masks", "mask_sums"]

# The weights are whole numbers (demonstration counts), so their sums are exact in any order:
# letting LLVM reassociate them (SIMD reductions) cannot change a result.
_SUMS = {"reassoc"}


@njit(cache=True, nogil=True, fastmath=_SUMS)
def sat_counts(viol, w_pos, w_neg):
    """Weighted numbers of acceptable / unacceptable rows that violate no clause."""
    ps = 0.0
    ns = 0.0
    for d in range(viol.shape[0]):
        ok = viol[d] == 0
        ps += w_pos[d] if ok else 0.0
        ns += w_neg[d] if ok else 0.0
    return ps, ns


@njit(cache=True, nogil=True, fastmath=_SUMS)
def flip_sums(viol, truth_t, c, inc, w_pos, w_neg):
    """Weighted satisfied counts without / with clause ``c`` (its bit is now ``inc``)."""
    # Weighted counts of demonstrations satisfying the hypothesis without / with clause c.
    ps_out = 0.0
    ns_out = 0.0
    ps_in = 0.0
    ns_in = 0.0
    for d in range(viol.shape[0]):
        t = truth_t[c, d]
        ok = viol[d] - (inc if t == 0 else 0) == 0
        both = ok and t != 0
        ps_out += w_pos[d] if ok else 0.0
        ns_out += w_neg[d] if ok else 0.0
        ps_in += w_pos[d] if both else 0.0
        ns_in += w_neg[d] if both else 0.0
    return ps_out, ns_out, ps_in, ns_in


@njit(cache=True, nogil=True, inline="always")
def zero_mask(viol, zmask):
    """The rows that violate no clause, as a bitset into ``zmask[0]``.

    A structure move only adds clauses to the hypothesis left once its subtask is taken out,
    so only these rows can satisfy a candidate: the candidates are weighed over them alone,
    as bitsets (``Demos.bits``) and weighted popcounts (``Demos.pos_planes``, ``neg_planes``).
    """
    # A word at a time, without branches (the rows past the last are never set).
    n_rows = viol.shape[0]
    for w in range(zmask.shape[1]):
        word = np.uint64(0)
        base = w << 6
        for b in range(min(64, n_rows - base)):
            word |= np.uint64(viol[base + b] == 0) << np.uint64(b)
        zmask[0, w] = word


@njit(cache=True, nogil=True, inline="always")
def weighted_popcount(word, planes, w):
    # The weight of the rows of one word: bit-plane k of the weights counts 2**k.
    total = 0
    for k in range(planes.shape[0]):
        total += popcount(word & planes[k, w]) << k
    return total


@njit(cache=True, nogil=True, inline="always")
def bit_sums(a, ia, b, ib, c, ic, demos):
    """:func:`flip_sums`' four sums (bit out) over ``a[ia] & b[ib]``, its clause ``c[ic]``.

    Weighted counts of the acceptable / unacceptable rows in ``a[ia] & b[ib]``, then in
    ``a[ia] & b[ib] & c[ic]``; whole numbers, so equal to the row-by-row sums. Rows of 2-D
    arrays, never slices: a view passed to a call costs reference counting (``_unmanaged``).
    """
    ps_out = 0
    ns_out = 0
    ps_in = 0
    ns_in = 0
    for w in range(a.shape[1]):
        out = a[ia, w] & b[ib, w]
        if out == 0:
            continue
        inn = out & c[ic, w]
        ps_out += weighted_popcount(out, demos.pos_planes, w)
        ns_out += weighted_popcount(out, demos.neg_planes, w)
        ps_in += weighted_popcount(inn, demos.pos_planes, w)
        ns_in += weighted_popcount(inn, demos.neg_planes, w)
    return float(ps_out), float(ns_out), float(ps_in), float(ns_in)


@njit(cache=True, nogil=True, inline="always")
def flip_masks(viol, masks):
    """The rows that violate no clause (``masks[0]``) and exactly one (``masks[1]``), as bitsets.

    What :func:`mask_sums` weighs a bit's two values over; rebuilt when a flip changes
    ``viol`` (rarely: most updates keep the bit).
    """
    n_rows = viol.shape[0]
    for w in range(masks.shape[1]):
        zero = np.uint64(0)
        one = np.uint64(0)
        base = w << 6
        for b in range(min(64, n_rows - base)):
            x = viol[base + b]
            zero |= np.uint64(x == 0) << np.uint64(b)
            one |= np.uint64(x == 1) << np.uint64(b)
        masks[0, w] = zero
        masks[1, w] = one


@njit(cache=True, nogil=True, inline="always")
def mask_sums(masks, c, inc, demos):
    """:func:`flip_sums`' four sums from :func:`flip_masks`' bitsets, in O(words x planes).

    With clause ``c`` in (``inc``), the rows satisfying the rest are those violating nothing
    or only ``c``; with it out, the rows satisfying it too are those violating nothing where
    ``c`` holds. Whole numbers, so equal to the row-by-row sums.
    """
    ps_out = 0
    ns_out = 0
    ps_in = 0
    ns_in = 0
    bits = demos.bits
    for w in range(masks.shape[1]):
        zero = masks[0, w]
        if inc:
            out = zero | (masks[1, w] & ~bits[c, w])
            inn = zero
        else:
            out = zero
            inn = zero & bits[c, w]
        if out == 0:
            continue
        ps_out += weighted_popcount(out, demos.pos_planes, w)
        ns_out += weighted_popcount(out, demos.neg_planes, w)
        if inn != 0:
            ps_in += weighted_popcount(inn, demos.pos_planes, w)
            ns_in += weighted_popcount(inn, demos.neg_planes, w)
    return float(ps_out), float(ns_out), float(ps_in), float(ns_in)
