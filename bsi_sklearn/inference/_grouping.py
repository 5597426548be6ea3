"""Grouping of hypothesis parts that the likelihood cannot tell apart.

A part of a hypothesis (an order structure, a subset of globals or of eventuals) enters the
likelihood only through the bitset of demonstrations it satisfies and its number of conjuncts.
Parts with the same ``(bitset, size)`` key form one group whose prior weights add up; the exact
enumeration then runs over groups instead of parts. This module holds the open-addressing hash
table (numba, no Python objects) that groups order structures as they are generated, and
``group_rows`` (numpy) for parts given as arrays; both assign group ids in order of first
appearance, so that the grouping, and every sum over groups, is deterministic.
"""

import math
from typing import NamedTuple

import numpy as np
from numba import njit

__all__ = ["KeyTable", "new_table", "with_room", "insert", "lookup", "add_weight",
           "group_rows", "Groups"]

_EMPTY = -1


class KeyTable(NamedTuple):
    """Hash table from ``(bitset words, size)`` keys to group ids ``0, 1, ...``."""

    slots: np.ndarray   # (capacity,) int64: group id, or -1 for an empty slot
    bits: np.ndarray    # (room, n_words) uint64: each group's bitset
    size: np.ndarray    # (room,) int64: each group's number of conjuncts
    count: np.ndarray   # (1,) int64: number of groups


class Groups(NamedTuple):
    """Groups of parts with their summed prior weight (linear, relative to ``ref``)."""

    bits: np.ndarray    # (G, n_words) uint64
    size: np.ndarray    # (G,) int64
    weight: np.ndarray  # (G,) float64: sum of exp(lp - ref) over the members
    ref: float          # log scale of ``weight``: the largest member log prior
    best: np.ndarray    # (G,) float64: largest member log prior of each group


@njit(cache=True, nogil=True)
def new_table(n_words, room):
    """An empty table for keys of ``n_words`` words, with space for ``room`` groups."""
    room = max(room, 16)
    cap = 1
    while cap < 2 * room:
        cap *= 2
    return KeyTable(np.full(cap, _EMPTY, dtype=np.int64),
                    np.empty((room, n_words), dtype=np.uint64),
                    np.empty(room, dtype=np.int64), np.zeros(1, dtype=np.int64))


@njit(cache=True, nogil=True, inline="always")
def _hash(bits, size):
    h = np.uint64(size) * np.uint64(0x9E3779B97F4A7C15)
    for w in range(bits.shape[0]):
        h ^= bits[w]
        h *= np.uint64(0xBF58476D1CE4E5B9)
        h ^= h >> np.uint64(31)
    return h


@njit(cache=True, nogil=True, inline="always")
def _slot_of(table, bits, size):
    # The slot holding the key, or the empty slot where it would go.
    mask = np.uint64(table.slots.shape[0] - 1)
    i = _hash(bits, size) & mask
    while True:
        g = table.slots[i]
        if g == _EMPTY:
            return i
        if table.size[g] == size:
            same = True
            for w in range(bits.shape[0]):
                if table.bits[g, w] != bits[w]:
                    same = False
                    break
            if same:
                return i
        i = (i + np.uint64(1)) & mask


@njit(cache=True, nogil=True)
def lookup(table, bits, size):
    """Group id of a key, or -1."""
    return table.slots[_slot_of(table, bits, size)]


@njit(cache=True, nogil=True)
def _grown(table):
    n = table.count[0]
    bigger = new_table(table.bits.shape[1], 2 * table.bits.shape[0])
    # Element loops, not slice copies: a slice copy compiles numba's shape-mismatch message
    # (string formatting), seconds of a cold start.
    for g in range(n):
        for w in range(table.bits.shape[1]):
            bigger.bits[g, w] = table.bits[g, w]
        bigger.size[g] = table.size[g]
    bigger.count[0] = n
    for g in range(n):
        bigger.slots[_slot_of(bigger, bigger.bits[g], bigger.size[g])] = g
    return bigger


@njit(cache=True, nogil=True)
def with_room(table):
    """The table itself, or a bigger copy when it is full (call before :func:`insert`)."""
    if table.count[0] == table.bits.shape[0]:
        return _grown(table)
    return table


@njit(cache=True, nogil=True)
def insert(table, bits, size):
    """Group id of the key, created if new; the table must have room (:func:`with_room`)."""
    i = _slot_of(table, bits, size)
    g = table.slots[i]
    if g != _EMPTY:
        return g
    g = table.count[0]
    table.slots[i] = g
    for w in range(bits.shape[0]):
        table.bits[g, w] = bits[w]
    table.size[g] = size
    table.count[0] = g + 1
    return g


@njit(cache=True, nogil=True)
def add_weight(weight, best, ref, g, lp, top):
    """Add a member of log weight ``lp`` to group ``g``; returns the (possibly raised) ``ref``.

    ``weight`` holds ``sum exp(lp - ref)``; when a member beats ``ref`` every weight is rescaled,
    so no term overflows. ``best[g]`` keeps the largest ``top`` (a member's largest log prior:
    ``lp`` itself for a single part, the sum of the parts' bests for a pair of groups).
    """
    if lp > ref:
        if ref > -np.inf:
            scale = math.exp(ref - lp)
            for i in range(weight.shape[0]):
                weight[i] *= scale
        ref = lp
    weight[g] += math.exp(lp - ref)
    if top > best[g]:
        best[g] = top
    return ref


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
