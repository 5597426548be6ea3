"""Order structures counted, not enumerated: dynamic programming over subsets of subtasks.

An order structure is a set of blocks, chains under Priors 1 and 2 and trees under Prior 3, and
its demonstration bitset is the AND of its blocks' bitsets. A chain on a subset ``S`` is a first
subtask ``f`` followed by a chain on ``S - f``; a tree on ``S`` is a root ``f`` above a forest on
``S - f``; either way the new orders are ``f -> u`` for every ``u`` in ``S - f``, whose bitset
AND that of the rest gives the block's. A structure on ``S`` is the block holding the lowest
subtask of ``S`` beside a structure on the rest. Every structure has exactly one such
derivation, so the tables below (for every subset, its blocks and its structures, grouped by
``(bitset, number of orders, number of chains)`` with summed prior weights and counts) hold
every structure of the support once. Structures that satisfy the same demonstrations are
summed however many there are: the work grows with the number of distinct groups per subset,
not with the support.

Both priors' weights factor over the derivation: chain structures depend only on their number
of chains (the last column of the key), and Prior 3 is ``forest_const + sum_v forest_g[size of
v's subtree]``, one factor per block. Groups whose acceptable demonstrations number fewer than
``thr`` are dropped as they appear (their bitsets only shrink as blocks are added).

:func:`bsi_sklearn.inference._structure_walk.descend` walks the tables back from the whole
set: the posterior mass of every group (its order-clause marginals) and, for the groups that
may hold a kept hypothesis, the derivations that
:func:`bsi_sklearn.inference._listing.list_hypotheses` enumerates.
"""

import math
from typing import NamedTuple

import numpy as np
from numba import njit

from bsi_sklearn._jit import helper
from bsi_sklearn.inference._structure_common import (
    BLOCK,
    COMBO_COST,
    ENTRY_COST,
    PART,
    STEP_COST,
    _Problem,
    _Scratch,
    and_pop,
    append_block,
    candidates,
    find,
    first_subtasks,
    n_bits,
    problem,
    scratch,
    whole_kind,
)

__all__ = ["StructureTables", "structure_tables", "whole_kind", "COMBO_COST", "STEP_COST",
           "ENTRY_COST"]

#: Still importable from here: numba's on-disk cache indexes of the kernels compiled before
#: these classes moved to _structure_common name them by this module, and numba unpickles an
#: index before it can tell that it is stale (an AttributeError instead of a recompilation).
_MOVED = (_Problem, _Scratch)


class StructureTables(NamedTuple):
    """Blocks and structures of every subset of subtasks, grouped (see the module docstring).

    Entry ids are shared by both kinds; entry 0 is the empty structure (and empty chain).
    The entries of kind ``k`` on subset ``s`` are ``lo[k, s]:hi[k, s]``; their true prior
    weights are ``weight * exp(ref[k, s])``.
    """

    bits: np.ndarray     # (E, n_words) uint64
    size: np.ndarray     # (E,) int64: number of orders
    aux: np.ndarray      # (E,) int64: number of chains (Priors 1, 2), 0 (Prior 3)
    weight: np.ndarray   # (E,) float64, relative to the subset's ref (largest is 1)
    best: np.ndarray     # (E,) float64: largest member log weight (absolute)
    count: np.ndarray    # (E,) float64: number of members
    lo: np.ndarray       # (2, 2**n) int64
    hi: np.ndarray       # (2, 2**n) int64
    ref: np.ndarray      # (2, 2**n) float64
    lists: np.ndarray    # the subsets with blocks, by lowest subtask (_structure_common)


# ----------------------------------------------------------------------------- inside pass
class _Store(NamedTuple):
    bits: np.ndarray
    size: np.ndarray
    aux: np.ndarray
    weight: np.ndarray
    best: np.ndarray
    count: np.ndarray


@njit(cache=True, nogil=True, inline="always")
def _entry_of(t_bits, t_size, t_aux, loc, stamp, cur, bits, size, aux, start, n_e):
    # The store entry of the key (bits, size, aux), new at n_e when absent: (entry, new end),
    # or (-1, n_e) when the hash table is over a quarter full with this step's entries, (-2,
    # n_e) when the store is full. The caller writes a new entry.
    i, e = find(loc, stamp, cur, t_bits, t_size, t_aux, bits, size, aux)
    if e >= 0:
        return e, n_e
    if 4 * (n_e - start + 1) > loc.shape[0]:
        return -1, n_e
    if n_e == t_size.shape[0]:
        return -2, n_e
    loc[i] = n_e
    stamp[i] = cur
    return n_e, n_e + 1


@njit(cache=True, nogil=True, inline="always")
def _new_entry(st, e, bits, size, aux):
    for w in range(bits.shape[0]):
        st.bits[e, w] = bits[w]
    st.size[e] = size
    st.aux[e] = aux
    st.weight[e] = 0.0
    st.best[e] = -np.inf
    st.count[e] = 0.0


@helper
def _block_step(pb, st, idx, s, fs, n_f, rs, ref_s, ht, cur, n_e, bits):
    # The blocks on s (f first or root, above a table entry on s - f) into the store from
    # n_e; returns the new end, or -1 (-2) when the hash table (the store) needs more room.
    t_bits, t_size, t_aux, weight, best, count = st
    lo, hi, ref = idx
    loc, stamp = ht
    kind, factor = pb.child_kind, pb.factor
    k_s = n_bits(s)
    no_aux = np.int64(0)  # not a literal 0: find compiles once
    start = n_e
    for j in range(n_f):
        c = s ^ (1 << fs[j])
        scale = math.exp(ref[kind, c] + factor[k_s] - ref_s)
        for z in range(lo[kind, c], hi[kind, c]):
            if and_pop(t_bits, z, rs, j, bits, pb.pos) < pb.thr:
                continue
            size = t_size[z] + k_s - 1
            e, end = _entry_of(t_bits, t_size, t_aux, loc, stamp, cur, bits, size, no_aux,
                               start, n_e)
            if e < 0:
                return e
            if end > n_e:
                _new_entry(st, e, bits, size, no_aux)
                n_e = end
            weight[e] += weight[z] * scale
            count[e] += count[z]
            best[e] = max(best[e], best[z] + factor[k_s])
    return n_e


@helper
def _part_step(pb, st, idx, s, cand, n_c, ref_s, ht, cur, n_e, bits):
    # The structures on s (a block holding s's lowest subtask beside a structure on the rest)
    # into the store from n_e; returns the new end, or -1 (-2) when the hash table (the
    # store) needs more room.
    t_bits, t_size, t_aux, weight, best, count = st
    lo, hi, ref = idx
    loc, stamp = ht
    start = n_e
    for j in range(n_c):
        b = cand[j]
        rest = s ^ b
        scale = math.exp(ref[BLOCK, b] + ref[PART, rest] - ref_s)
        for x in range(lo[BLOCK, b], hi[BLOCK, b]):
            for y in range(lo[PART, rest], hi[PART, rest]):
                if and_pop(t_bits, x, t_bits, y, bits, pb.pos) < pb.thr:
                    continue
                size = t_size[x] + t_size[y]
                aux = t_aux[x] + t_aux[y] + pb.aux_inc
                e, end = _entry_of(t_bits, t_size, t_aux, loc, stamp, cur, bits, size, aux,
                                   start, n_e)
                if e < 0:
                    return e
                if end > n_e:
                    _new_entry(st, e, bits, size, aux)
                    n_e = end
                weight[e] += weight[x] * weight[y] * scale
                count[e] += count[x] * count[y]
                best[e] = max(best[e], best[x] + best[y])
    return n_e


def _new_store(room, n_words):
    # Every entry is written (_new_entry) before it is read: no need to fill.
    return _Store(np.empty((room, n_words), dtype=np.uint64), np.empty(room, dtype=np.int64),
                  np.empty(room, dtype=np.int64), np.empty(room), np.empty(room), np.empty(room))


def _more_room(st, ht, code):
    # A step stopped on a full table (-1: the hash table, -2: the store): twice the room. The
    # store only ever holds the groups found, never as many entries as combinations counted.
    if code == -2:
        k = st.weight.shape[0]
        big = _new_store(2 * k, st.bits.shape[1])
        for old, new in zip(st, big):
            new[:k] = old
        return big, ht
    cap = 2 * ht[0].shape[0]
    return st, (np.zeros(cap, dtype=np.int64), np.zeros(cap, dtype=np.int64))


@helper
def _close(weight, start, stop, ref_s):
    # Rescale a subset's weights so that the largest is 1; returns its new ref.
    if stop == start:
        return -np.inf
    top = 0.0
    for e in range(start, stop):
        top = max(top, weight[e])
    if top > 0.0:
        for e in range(start, stop):
            weight[e] /= top
        return ref_s + math.log(top)
    return ref_s


# Where _inside is (an int64 array, so that it can stop on a full table and be called again
# where it stopped once Python has made room): the subset, the kind of step, the store's end,
# the hash table's stamp, the work counted, and whether the step's work is already counted.
_S, _KIND, _END, _CUR, _WORK, _COUNTED = range(6)


@njit(cache=True, nogil=True)
def _inside(pb, st, ht, idx, lists, scr, at, max_work):
    # The tables from subset at[_S] on; returns 0 (done), 1 (the work passed max_work), or
    # -1 (-2) when the hash table (the store) needs more room, `at` telling where it stopped.
    n = pb.n
    lo, hi, ref = idx
    fs, rs, cand = scr.fs, scr.rs, scr.cand
    s = at[_S]
    kind = at[_KIND]
    n_e = at[_END]
    cur = at[_CUR]
    work = at[_WORK]
    counted = at[_COUNTED]
    code = 0
    while s < lo.shape[1]:
        if kind == BLOCK:
            # Blocks on s; the work of every step is counted before it is done.
            n_f, n_comb, steps = first_subtasks(pb, lo, hi, s, fs, rs)
            ref_s = -np.inf
            for j in range(n_f):
                ref_s = max(ref_s, ref[pb.child_kind, s ^ (1 << fs[j])] + pb.factor[n_bits(s)])
            if not counted:
                work += STEP_COST * steps + COMBO_COST * n_comb
                counted = 1
                if work > max_work:  # also when the last step's entries passed it
                    code = 1
                    break
            cur += 1
            stop = _block_step(pb, st, idx, s, fs, n_f, rs, ref_s, ht, cur, n_e, scr.bits)
        else:
            # Structures on s.
            n_c, steps = candidates(s, n, lo, hi, lists, cand)
            ref_s = -np.inf
            n_comb = 0
            for j in range(n_c):
                b = cand[j]
                ref_s = max(ref_s, ref[BLOCK, b] + ref[PART, s ^ b])
                n_comb += (hi[BLOCK, b] - lo[BLOCK, b]) * (hi[PART, s ^ b] - lo[PART, s ^ b])
            if not counted:
                work += STEP_COST * steps + COMBO_COST * n_comb
                counted = 1
                if work > max_work:
                    code = 1
                    break
            cur += 1
            stop = _part_step(pb, st, idx, s, cand, n_c, ref_s, ht, cur, n_e, scr.bits)
        if stop < 0:  # again with more room (rarely)
            code = stop
            break
        lo[kind, s], hi[kind, s] = n_e, stop
        ref[kind, s] = _close(st.weight, n_e, stop, ref_s)
        if kind == BLOCK and stop > n_e:
            append_block(lists, s, lo.shape[1], n)
        work += ENTRY_COST * (stop - n_e)
        n_e = stop
        counted = 0
        if kind == BLOCK and pb.use_part:
            kind = PART
        else:
            kind = BLOCK
            s += 1
    at[_S], at[_KIND], at[_END], at[_CUR], at[_WORK], at[_COUNTED] = (s, kind, n_e, cur, work,
                                                                      counted)
    return code


def structure_tables(clause_bits, full, pos, thr, model, max_work=np.inf, max_entries=2**62):
    """Group every order structure of the model's prior by (bitset, orders, chains).

    Parameters
    ----------
    clause_bits : ndarray (n_clauses, n_words) uint64
    full, pos : ndarray (n_words,) uint64
        All demonstrations; the acceptable ones.
    thr : int
        Groups (and partial structures) satisfying fewer acceptable demonstrations are dropped.
    model : Model
    max_work : float
        Stop before the work would exceed this (units of :data:`COMBO_COST`,
        :data:`STEP_COST`, :data:`ENTRY_COST`; it depends on the data only). A step's
        combinations are counted before it runs, its new entries after (so the memory passes
        the budget by one step's entries at most).
    max_entries : int
        Most entries the store may hold (``_budget.entry_bytes`` each); a store that
        would grow past it stops the tables as the work budget does.

    Returns
    -------
    tables : StructureTables or None
        None when the work would exceed ``max_work`` or the store ``max_entries``.
    work : int
        The work counted (done, or that would have been done up to the step that stopped).
    """
    pb = problem(clause_bits, full, pos, thr, model)
    n, n_words = pb.n, full.shape[0]
    n_sets = 1 << n
    st = _new_store(1024, n_words)
    st.bits[0] = full  # entry 0: the empty structure (and chain)
    st.size[0] = st.aux[0] = 0
    st.weight[0], st.best[0], st.count[0] = 1.0, 0.0, 1.0
    lo = np.zeros((2, n_sets), dtype=np.int64)
    hi = np.zeros((2, n_sets), dtype=np.int64)
    ref = np.full((2, n_sets), -np.inf)
    hi[:, 0] = 1
    ref[:, 0] = 0.0
    lists = np.full(n_sets + 3 * n, -1, dtype=np.int64)
    lists[n_sets + 2 * n:] = 0
    ht = (np.zeros(1024, dtype=np.int64), np.zeros(1024, dtype=np.int64))
    at = np.zeros(6, dtype=np.int64)
    at[_S], at[_END] = 1, 1
    scr = scratch(n, n_words)
    max_work = int(min(max_work, 2**62))
    while True:
        code = _inside(pb, st, ht, (lo, hi, ref), lists, scr, at, max_work)
        if code >= 0:
            break
        if code == -2 and 2 * st.weight.shape[0] > min(max_entries, 2**62):
            return None, int(at[_WORK])  # the store would pass its memory
        st, ht = _more_room(st, ht, code)
    if code == 1 or at[_WORK] > max_work:
        return None, int(at[_WORK])
    n_e = at[_END]
    return StructureTables(*[a[:n_e].copy() for a in st], lo, hi, ref, lists), int(at[_WORK])
