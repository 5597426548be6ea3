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

:func:`descend` walks the tables back from the whole set: the posterior mass of every group
(its order-clause marginals) and, for the groups that may hold a kept hypothesis, the
derivations :func:`bsi_sklearn.inference._exact_kernels.list_hypotheses` enumerates.
"""

import math
from typing import NamedTuple

import numpy as np
from numba import njit

from bsi_sklearn.clauses import popcount
from bsi_sklearn.inference._grouping import KeyTable, insert, lookup, new_table, with_room

__all__ = ["StructureTables", "structure_tables", "whole_kind", "descend", "COMBO_COST",
           "STEP_COST"]

_BLOCK = 0
_PART = 1
#: By prior code: whether structures are sets of blocks (True) or one block (Prior 1: a chain).
PRIOR_SETS = (False, True, True)
#: Work units (evaluations of a pair of groups, about 5-10 ns) of one combination of two table
#: entries (an AND, a popcount, a hash probe), and of one step over subsets.
COMBO_COST = 4
STEP_COST = 1


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
    keys: np.ndarray     # (E,) int64: the hash key's size field (subset, kind, chains, orders)
    slots: np.ndarray    # the hash table's slots (a KeyTable with bits and keys)
    lists: np.ndarray    # the subsets with blocks, by lowest subtask (see _append_block)


class _Problem(NamedTuple):
    # What both passes over the tables read.
    clause_bits: np.ndarray  # (n_clauses, n_words) uint64
    base: int                # index of the first order clause (a -> b at base + a * n + b)
    n: int
    full: np.ndarray         # (n_words,) every demonstration
    pos: np.ndarray          # (n_words,) the acceptable ones
    thr: int                 # fewest acceptable demonstrations a kept entry satisfies
    factor: np.ndarray       # (n + 2,) log weight of a block by its number of subtasks
    aux_inc: int             # 1: count the blocks of a structure (chains), 0: not (trees)
    child_kind: int          # what a block's first subtask (or root) is above
    use_part: bool           # structures are sets of blocks (else one block: Prior 1)


def whole_kind(model):
    """Which table (0: blocks, 1: structures) holds the whole structures of the model's prior."""
    return _PART if PRIOR_SETS[model.prior] or model.n == 0 else _BLOCK


def _problem(clause_bits, full, pos, thr, model):
    n = model.n
    chains = not model.forest
    factor = np.zeros(n + 2) if chains else np.asarray(model.forest_g, dtype=np.float64)
    return _Problem(clause_bits, model.n_g + n, n, full, pos, int(thr), factor,
                    1 if chains else 0, _BLOCK if chains else _PART, PRIOR_SETS[model.prior])


@njit(cache=True, nogil=True, inline="always")
def _key(s, kind, aux, size, n):
    return ((s * 2 + kind) * (n + 2) + aux) * (n * (n - 1) // 2 + 1) + size


@njit(cache=True, nogil=True, inline="always")
def _and_pop(a, b, out, pos):
    p = 0
    for w in range(out.shape[0]):
        out[w] = a[w] & b[w]
        p += popcount(out[w] & pos[w])
    return p


@njit(cache=True, nogil=True)
def _orders_from(clause_bits, base, n, f, rest, full, r):
    # r = AND of the clauses f -> u, u in rest.
    r[:] = full
    for u in range(n):
        if (rest >> u) & 1:
            for w in range(r.shape[0]):
                r[w] &= clause_bits[base + f * n + u, w]


@njit(cache=True, nogil=True)
def _grow(a, room, fill):
    b = np.full(room, fill, dtype=a.dtype)
    b[:a.shape[0]] = a
    return b


@njit(cache=True, nogil=True, inline="always")
def _lowest(s):
    i = 0
    while not (s >> i) & 1:
        i += 1
    return i


@njit(cache=True, nogil=True)
def _append_block(lists, s, n_sets, n):
    # lists: next subset at [s], then by lowest subtask i: head, tail, length at n_sets + (0,
    # 1, 2) * n + i (the subsets whose block tables are not empty, in increasing order).
    i = _lowest(s)
    if lists[n_sets + n + i] >= 0:
        lists[lists[n_sets + n + i]] = s
    else:
        lists[n_sets + i] = s
    lists[n_sets + n + i] = s
    lists[n_sets + 2 * n + i] += 1


@njit(cache=True, nogil=True)
def _new_lists(n_sets, n):
    lists = np.full(n_sets + 3 * n, -1, dtype=np.int64)
    lists[n_sets + 2 * n:] = 0
    return lists


@njit(cache=True, nogil=True)
def _candidates(s, n, hi, lo, lists, out):
    # Blocks B (non-empty tables) holding the lowest subtask of s, with s - B non-empty too:
    # by submasks of s or through the list of blocks with that lowest subtask, whichever is
    # shorter. Returns how many (into out) and the steps taken.
    n_sets = lo.shape[1]
    i = _lowest(s)
    low = 1 << i
    rest0 = s ^ low
    k = 0
    steps = 0
    if (1 << popcount_int(rest0)) <= lists[n_sets + 2 * n + i]:
        sub = rest0
        while True:
            b = sub | low
            steps += 1
            if hi[_BLOCK, b] > lo[_BLOCK, b] and hi[_PART, s ^ b] > lo[_PART, s ^ b]:
                out[k] = b
                k += 1
            if sub == 0:
                break
            sub = (sub - 1) & rest0
    else:
        b = lists[n_sets + i]
        while b >= 0:
            steps += 1
            if (b & s) == b and hi[_PART, s ^ b] > lo[_PART, s ^ b]:
                out[k] = b
                k += 1
            b = lists[b]
    return k, steps


@njit(cache=True, nogil=True, inline="always")
def popcount_int(x):
    c = 0
    while x:
        x &= x - 1
        c += 1
    return c


@njit(cache=True, nogil=True)
def _inside(pb, max_work):
    clause_bits, base, n, full, pos, thr = pb.clause_bits, pb.base, pb.n, pb.full, pb.pos, pb.thr
    factor, aux_inc, child_kind, use_part = pb.factor, pb.aux_inc, pb.child_kind, pb.use_part
    n_sets = 1 << n
    n_words = full.shape[0]
    table = new_table(n_words, 1024)
    room = table.bits.shape[0]
    size = np.zeros(room, dtype=np.int64)
    aux = np.zeros(room, dtype=np.int64)
    weight = np.zeros(room)
    best = np.full(room, -np.inf)
    count = np.zeros(room)
    lo = np.zeros((2, n_sets), dtype=np.int64)
    hi = np.zeros((2, n_sets), dtype=np.int64)
    ref = np.full((2, n_sets), -np.inf)
    insert(table, full, _key(0, _PART, 0, 0, n))
    weight[0] = 1.0
    best[0] = 0.0
    count[0] = 1.0
    hi[:, 0] = 1
    ref[:, 0] = 0.0
    lists = _new_lists(n_sets, n)
    cand = np.empty(max(1, n_sets >> 1), dtype=np.int64)
    r = np.empty(n_words, dtype=np.uint64)
    bits = np.empty(n_words, dtype=np.uint64)
    work = 0
    for s in range(1, n_sets):
        k_s = popcount_int(s)
        # Blocks on s: f first (or root), then a chain (or forest) on s - f.
        top = -np.inf
        for f in range(n):
            c = s ^ (1 << f)
            if (s >> f) & 1 and hi[child_kind, c] > lo[child_kind, c]:
                top = max(top, ref[child_kind, c])
        start = table.count[0]
        ref_s = top + factor[k_s]
        if top > -np.inf:
            for f in range(n):
                c = s ^ (1 << f)
                if not (s >> f) & 1 or hi[child_kind, c] == lo[child_kind, c]:
                    continue
                _orders_from(clause_bits, base, n, f, c, full, r)
                work += STEP_COST * k_s
                p = 0
                for w in range(n_words):
                    p += popcount(r[w] & pos[w])
                if p < thr:
                    continue
                scale = math.exp(ref[child_kind, c] + factor[k_s] - ref_s)
                for z in range(lo[child_kind, c], hi[child_kind, c]):
                    work += COMBO_COST
                    if _and_pop(table.bits[z], r, bits, pos) < thr:
                        continue
                    if table.count[0] == table.bits.shape[0]:
                        table, size, aux, weight, best, count = _grown(table, size, aux,
                                                                        weight, best, count)
                    new = table.count[0]
                    e = insert(table, bits, _key(s, _BLOCK, 0, size[z] + k_s - 1, n))
                    if e == new:
                        size[e] = size[z] + k_s - 1
                    weight[e] += weight[z] * scale
                    count[e] += count[z]
                    best[e] = max(best[e], best[z] + factor[k_s])
        ref_s = _close(weight, start, table.count[0], ref_s)
        lo[_BLOCK, s], hi[_BLOCK, s], ref[_BLOCK, s] = start, table.count[0], ref_s
        if table.count[0] > start:
            _append_block(lists, s, n_sets, n)
        if work > max_work:
            return False, table, size, aux, weight, best, count, lo, hi, ref, lists, work
        if not use_part:
            continue
        # Structures on s: the block holding s's lowest subtask, and a structure on the rest.
        n_c, steps = _candidates(s, n, hi, lo, lists, cand)
        work += STEP_COST * steps
        top = -np.inf
        for j in range(n_c):
            top = max(top, ref[_BLOCK, cand[j]] + ref[_PART, s ^ cand[j]])
        start = table.count[0]
        ref_s = top
        for j in range(n_c):
            b = cand[j]
            rest = s ^ b
            scale = math.exp(ref[_BLOCK, b] + ref[_PART, rest] - ref_s)
            for x in range(lo[_BLOCK, b], hi[_BLOCK, b]):
                for y in range(lo[_PART, rest], hi[_PART, rest]):
                    work += COMBO_COST
                    if _and_pop(table.bits[x], table.bits[y], bits, pos) < thr:
                        continue
                    if table.count[0] == table.bits.shape[0]:
                        table, size, aux, weight, best, count = _grown(table, size, aux,
                                                                        weight, best, count)
                    new = table.count[0]
                    a = aux[x] + aux[y] + aux_inc
                    e = insert(table, bits, _key(s, _PART, a, size[x] + size[y], n))
                    if e == new:
                        size[e] = size[x] + size[y]
                        aux[e] = a
                    weight[e] += weight[x] * weight[y] * scale
                    count[e] += count[x] * count[y]
                    best[e] = max(best[e], best[x] + best[y])
            if work > max_work:
                return False, table, size, aux, weight, best, count, lo, hi, ref, lists, work
        ref_s = _close(weight, start, table.count[0], ref_s)
        lo[_PART, s], hi[_PART, s], ref[_PART, s] = start, table.count[0], ref_s
        if work > max_work:
            return False, table, size, aux, weight, best, count, lo, hi, ref, lists, work
    return True, table, size, aux, weight, best, count, lo, hi, ref, lists, work


@njit(cache=True, nogil=True)
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


@njit(cache=True, nogil=True)
def _grown(table, size, aux, weight, best, count):
    table = with_room(table)
    room = table.bits.shape[0]
    return (table, _grow(size, room, 0), _grow(aux, room, 0), _grow(weight, room, 0.0),
            _grow(best, room, -np.inf), _grow(count, room, 0.0))


def structure_tables(clause_bits, full, pos, thr, model, max_work=np.inf):
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
        Stop after this much work (units of :data:`COMBO_COST`, :data:`STEP_COST`).

    Returns
    -------
    tables : StructureTables or None
        None when the work exceeded ``max_work``.
    work : int
        The work done.
    """
    limit = int(min(max_work, 2**62))
    ok, table, size, aux, weight, best, count, lo, hi, ref, lists, work = _inside(
        _problem(clause_bits, full, pos, thr, model), limit)
    if not ok:
        return None, int(work)
    k = table.count[0]
    return StructureTables(table.bits[:k].copy(), size[:k].copy(), aux[:k].copy(),
                           weight[:k].copy(), best[:k].copy(), count[:k].copy(), lo, hi, ref,
                           table.size[:k].copy(), table.slots, lists), int(work)


@njit(cache=True, nogil=True)
def _descend(tabs, table, pb, out, mark):
    # From the whole set down: posterior mass per unit weight (out) of every entry, the
    # order-clause marginals, and the derivations (records) of the marked entries.
    clause_bits, base, n, full, pos, thr = pb.clause_bits, pb.base, pb.n, pb.full, pb.pos, pb.thr
    factor, aux_inc, child_kind, use_part = pb.factor, pb.aux_inc, pb.child_kind, pb.use_part
    t_bits, t_size, t_aux, t_weight = tabs.bits, tabs.size, tabs.aux, tabs.weight
    lo, hi, ref = tabs.lo, tabs.hi, tabs.ref
    n_sets = 1 << n
    n_words = full.shape[0]
    marg_fs = np.zeros(n)
    marg = np.zeros(n * n)
    room = 1024
    rec = np.empty((room, 4), dtype=np.int64)
    n_rec = 0
    lists = tabs.lists
    cand = np.empty(max(1, n_sets >> 1), dtype=np.int64)
    r = np.empty(n_words, dtype=np.uint64)
    bits = np.empty(n_words, dtype=np.uint64)
    for s in range(n_sets - 1, 0, -1):
        k_s = popcount_int(s)
        if use_part and _live(out, mark, lo[_PART, s], hi[_PART, s]):
            n_c, _ = _candidates(s, n, hi, lo, lists, cand)
            for j in range(n_c):
                b = cand[j]
                rest = s ^ b
                scale = math.exp(ref[_BLOCK, b] + ref[_PART, rest] - ref[_PART, s])
                for x in range(lo[_BLOCK, b], hi[_BLOCK, b]):
                    for y in range(lo[_PART, rest], hi[_PART, rest]):
                        if _and_pop(t_bits[x], t_bits[y], bits, pos) < thr:
                            continue
                        a = t_aux[x] + t_aux[y] + aux_inc
                        e = lookup(table, bits, _key(s, _PART, a, t_size[x] + t_size[y], n))
                        if e < 0:
                            continue
                        if out[e] > 0.0:
                            out[x] += out[e] * t_weight[y] * scale
                            out[y] += out[e] * t_weight[x] * scale
                        if mark[e]:
                            mark[x] = 1
                            mark[y] = 1
                            rec, n_rec = _record(rec, n_rec, e, x, y, -1)
        if not _live(out, mark, lo[_BLOCK, s], hi[_BLOCK, s]):
            continue
        marg_fs[:] = 0.0
        for f in range(n):
            c = s ^ (1 << f)
            if not (s >> f) & 1 or hi[child_kind, c] == lo[child_kind, c]:
                continue
            _orders_from(clause_bits, base, n, f, c, full, r)
            scale = math.exp(ref[child_kind, c] + factor[k_s] - ref[_BLOCK, s])
            for z in range(lo[child_kind, c], hi[child_kind, c]):
                if _and_pop(t_bits[z], r, bits, pos) < thr:
                    continue
                e = lookup(table, bits, _key(s, _BLOCK, 0, t_size[z] + k_s - 1, n))
                if e < 0:
                    continue
                if out[e] > 0.0:
                    out[z] += out[e] * scale
                    marg_fs[f] += out[e] * t_weight[z] * scale
                if mark[e]:
                    mark[z] = 1
                    rec, n_rec = _record(rec, n_rec, e, z, -1, f)
        for f in range(n):
            if marg_fs[f] > 0.0:
                for u in range(n):
                    if u != f and (s >> u) & 1:
                        marg[f * n + u] += marg_fs[f]
    return marg, rec[:n_rec]


@njit(cache=True, nogil=True, inline="always")
def _live(out, mark, start, stop):
    for e in range(start, stop):
        if out[e] > 0.0 or mark[e]:
            return True
    return False


@njit(cache=True, nogil=True)
def _record(rec, n_rec, e, a, b, f):
    if n_rec == rec.shape[0]:
        bigger = np.empty((2 * n_rec, 4), dtype=np.int64)
        bigger[:n_rec] = rec
        rec = bigger
    rec[n_rec, 0] = e
    rec[n_rec, 1] = a
    rec[n_rec, 2] = b
    rec[n_rec, 3] = f
    return rec, n_rec + 1


def descend(tables, clause_bits, full, pos, thr, model, top_ids, top_out, marked):
    """Order-clause marginals and the derivations of the marked entries.

    Parameters
    ----------
    tables : StructureTables
        From :func:`structure_tables` with the same ``thr``.
    top_ids : ndarray (n_top,)
        The entries holding whole structures (``whole_kind``'s entries on the whole set).
    top_out : ndarray (n_top,)
        Posterior mass per unit (stored) weight of each.
    marked : ndarray (n_top,) bool
        The whole-set entries whose structures are to be listed.

    Returns
    -------
    marg : ndarray (n * n,)
        Posterior mass of each order ``a -> v`` at ``a * n + v``.
    rec_start, rec : ndarray
        For entry ``e``, ``rec[rec_start[e]:rec_start[e + 1]]`` are its derivations: rows
        ``(entry, a, b, f)``, a block's ``f`` first (or root) above entry ``a``
        (``b = -1``), or a structure's block ``a`` beside the structure ``b`` (``f = -1``).
    """
    out = np.zeros(len(tables.weight))
    out[top_ids] = top_out
    mark = np.zeros(len(tables.weight), dtype=np.uint8)
    mark[top_ids[marked]] = 1
    table = KeyTable(tables.slots, tables.bits, tables.keys,
                     np.full(1, len(tables.weight), dtype=np.int64))
    marg, rec = _descend(tables, table, _problem(clause_bits, full, pos, thr, model), out,
                         mark)
    order = np.argsort(rec[:, 0], kind="stable")
    rec = rec[order]
    rec_start = np.searchsorted(rec[:, 0], np.arange(len(tables.weight) + 1)).astype(np.int64)
    return marg, rec_start, rec

