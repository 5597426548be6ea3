"""Grouping of hypothesis parts that the likelihood cannot tell apart.

A part of a hypothesis (an order structure, a subset of globals or of eventuals) enters the
likelihood only through the bitset of demonstrations it satisfies and its number of conjuncts.
Parts with the same ``(bitset, size)`` key form one group whose prior weights add up; the exact
enumeration then runs over groups instead of parts. This module holds ``group_rows`` (numpy),
which groups parts given as arrays and assigns group ids in order of first appearance, so that
the grouping, and every sum over groups, is deterministic (the order structures are grouped as
they are generated, in the tables of :mod:`bsi_sklearn.inference._structures`).
"""

from typing import NamedTuple

import numpy as np

__all__ = ["group_rows", "Groups"]


class Groups(NamedTuple):
    """Groups of parts with their summed prior weight (linear, relative to ``ref``)."""

    bits: np.ndarray    # (G, n_words) uint64
    size: np.ndarray    # (G,) int64
    weight: np.ndarray  # (G,) float64: sum of exp(lp - ref) over the members
    ref: float          # log scale of ``weight``: the largest member log prior
    best: np.ndarray    # (G,) float64: largest member log prior of each group


_MIX = np.uint64(0x9E3779B97F4A7C15)


def _unique_rows(key):
    # The distinct rows of key, each row's first index and every row's distinct row (in no
    # particular order: group_rows orders them by first appearance), by a hash of each row:
    # sorting one uint64 a row is tens of times faster than np.unique(axis=0) on rows of
    # several words. Equal hashes of different rows (checked, never assumed away) take
    # np.unique's own way.
    h = np.zeros(len(key), dtype=np.uint64)
    for w in range(key.shape[1]):
        h = (h ^ key[:, w]) * _MIX
        h ^= h >> np.uint64(29)
    _, first, inverse = np.unique(h, return_index=True, return_inverse=True)
    if not np.array_equal(key[first][inverse.ravel()], key):
        _, first, inverse = np.unique(key, axis=0, return_index=True, return_inverse=True)
    return key[first], first, inverse.ravel()


def group_rows(bits, size, lp, top=None):
    """Group rows by ``(bits, size)``; rows of log weight ``-inf`` get group ``-1``.

    ``lp`` is each row's log weight (its log prior); ``top`` the log prior of its most probable
    member (``lp`` itself by default), of which each group keeps the largest. Plain numpy: the
    subsets it groups are few, and it spares a compilation on the first fit.

    Returns
    -------
    gid : ndarray of shape (n_rows,), int64
        Each row's group (ids in order of first appearance).
    groups : Groups

    Examples
    --------
    >>> bits = np.array([[1], [2], [1]], dtype=np.uint64)
    >>> gid, g = group_rows(bits, np.array([1, 1, 1]), np.log([0.5, 0.3, 0.2]))
    >>> gid.tolist(), np.round(g.weight * np.exp(g.ref), 3).tolist()
    ([0, 1, 0], [0.7, 0.3])
    """
    bits = np.asarray(bits, dtype=np.uint64).reshape(len(lp), -1)
    lp = np.asarray(lp, dtype=np.float64)
    top = lp if top is None else np.asarray(top, dtype=np.float64)
    ok = lp > -np.inf
    gid = np.full(len(lp), -1, dtype=np.int64)
    if not ok.any():
        return gid, Groups(np.empty((0, bits.shape[1]), np.uint64), np.empty(0, np.int64),
                           np.empty(0), -np.inf, np.empty(0))
    key = np.concatenate([bits[ok], np.asarray(size, dtype=np.uint64)[ok, None]], axis=1)
    uniq, first, inverse = _unique_rows(key)
    order = np.argsort(first, kind="stable")  # ids in order of first appearance
    rank = np.empty(len(order), dtype=np.int64)
    rank[order] = np.arange(len(order))
    gid[ok] = rank[inverse.ravel()]
    ref = float(lp[ok].max())
    weight = np.zeros(len(order))
    np.add.at(weight, gid[ok], np.exp(lp[ok] - ref))
    best = np.full(len(order), -np.inf)
    np.maximum.at(best, gid[ok], top[ok])
    return gid, Groups(np.ascontiguousarray(uniq[order, :-1]), uniq[order, -1].astype(np.int64),
                       weight, ref, best)
