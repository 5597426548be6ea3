"""The walk back down the structure tables (:mod:`bsi_sklearn.inference._structures`).

From the whole set of subtasks down to single subtasks, every entry passes its posterior mass
(per unit of its stored weight) to the two entries each of its derivations combines, in
proportion to the other's weight; a block's derivation also gives its mass to the orders
``f -> u`` it adds, which sums to the order-clause marginals. The entries of the structure
groups that may hold a kept hypothesis are marked, the marks passed down the same way, and the
derivations of every marked entry recorded: they are all
:func:`bsi_sklearn.inference._listing.list_hypotheses` needs to rebuild those structures.
"""

import math

import numpy as np
from numba import njit

from bsi_sklearn._jit import helper
from bsi_sklearn.inference._structure_common import (
    BLOCK,
    PART,
    and_pop,
    candidates,
    find,
    first_subtasks,
    n_bits,
    problem,
    scratch,
)

__all__ = ["descend"]


@helper
def _part_down(pb, tabs, s, cand, n_c, ht, cur, acc, rec, n_rec, bits):
    # Mass (and marks, with their derivations) of the structures on s, to their parts.
    out, mark, _ = acc
    loc, stamp = ht
    lo, hi, ref = tabs.lo, tabs.hi, tabs.ref
    for j in range(n_c):
        b = cand[j]
        rest = s ^ b
        scale = math.exp(ref[BLOCK, b] + ref[PART, rest] - ref[PART, s])
        for x in range(lo[BLOCK, b], hi[BLOCK, b]):
            for y in range(lo[PART, rest], hi[PART, rest]):
                if and_pop(tabs.bits, x, tabs.bits, y, bits, pb.pos) < pb.thr:
                    continue
                _, e = find(loc, stamp, cur, tabs.bits, tabs.size, tabs.aux, bits,
                            tabs.size[x] + tabs.size[y], tabs.aux[x] + tabs.aux[y] + pb.aux_inc)
                if e < 0:  # cannot happen: the inside pass made every entry it combines into
                    continue
                if out[e] > 0.0:
                    out[x] += out[e] * tabs.weight[y] * scale
                    out[y] += out[e] * tabs.weight[x] * scale
                if mark[e]:
                    mark[x] = 1
                    mark[y] = 1
                    rec[n_rec, 0], rec[n_rec, 1], rec[n_rec, 2], rec[n_rec, 3] = e, x, y, -1
                    n_rec += 1
    return n_rec


@helper
def _block_down(pb, tabs, s, fs, n_f, rs, ht, cur, acc, rec, n_rec, bits):
    # Mass (and marks) of the blocks on s, to their rests; the orders f -> u get the mass.
    out, mark, marg = acc
    loc, stamp = ht
    lo, hi, ref = tabs.lo, tabs.hi, tabs.ref
    k_s = n_bits(s)
    for j in range(n_f):
        f = fs[j]
        c = s ^ (1 << f)
        scale = math.exp(ref[pb.child_kind, c] + pb.factor[k_s] - ref[BLOCK, s])
        mass = 0.0
        for z in range(lo[pb.child_kind, c], hi[pb.child_kind, c]):
            if and_pop(tabs.bits, z, rs, j, bits, pb.pos) < pb.thr:
                continue
            _, e = find(loc, stamp, cur, tabs.bits, tabs.size, tabs.aux, bits,
                        tabs.size[z] + k_s - 1, np.int64(0))  # not a literal 0
            if e < 0:
                continue
            if out[e] > 0.0:
                out[z] += out[e] * scale
                mass += out[e] * tabs.weight[z] * scale
            if mark[e]:
                mark[z] = 1
                rec[n_rec, 0], rec[n_rec, 1], rec[n_rec, 2], rec[n_rec, 3] = e, z, -1, f
                n_rec += 1
        if mass > 0.0:
            for u in range(pb.n):
                if u != f and (s >> u) & 1:
                    marg[f * pb.n + u] += mass
    return n_rec


@njit(cache=True, nogil=True, inline="always")
def _live(out, mark, start, stop):
    held = False
    marked = False
    for e in range(start, stop):
        held |= out[e] > 0.0
        marked |= mark[e] != 0
    return held or marked, marked


@helper
def _local_table(ht, cur, st, start, stop):
    # The subset's hash table holding entries start:stop (descend made it big enough).
    loc, stamp = ht
    for e in range(start, stop):
        i, _ = find(loc, stamp, cur, st.bits, st.size, st.aux, st.bits[e], st.size[e],
                    st.aux[e])
        loc[i] = e
        stamp[i] = cur


# Where _descend is (an int64 array, so that it can stop when the records are full and be
# called again where it stopped once Python has made room): the subset, the kind of step, the
# number of records and the hash table's stamp.
_S, _KIND, _N_REC, _CUR = range(4)


@njit(cache=True, nogil=True)
def _descend(tabs, pb, acc, rec, ht, scr, at):
    # From the whole set down: posterior mass per unit weight (out) of every entry, the
    # order-clause marginals, and the derivations (records) of the marked entries. Returns 0
    # when done, or the number of records needed when rec is too small for the next step.
    n = pb.n
    lo, hi = tabs.lo, tabs.hi
    out, mark, _ = acc
    cand, fs, rs, bits = scr.cand, scr.fs, scr.rs, scr.bits
    s = at[_S]
    kind = at[_KIND]
    n_rec = at[_N_REC]
    cur = at[_CUR]
    need = 0
    while s > 0:
        live, marked = _live(out, mark, lo[kind, s], hi[kind, s])
        if kind == PART and not (pb.use_part and live):
            kind = BLOCK
            continue
        if kind == BLOCK and not live:
            kind = PART
            s -= 1
            continue
        if kind == PART:
            n_c, _ = candidates(s, n, lo, hi, tabs.lists, cand)
            if marked:
                n_comb = 0
                for j in range(n_c):
                    b = cand[j]
                    n_comb += ((hi[BLOCK, b] - lo[BLOCK, b])
                               * (hi[PART, s ^ b] - lo[PART, s ^ b]))
                if n_rec + n_comb > rec.shape[0]:
                    need = n_rec + n_comb
                    break
            cur += 1
            _local_table(ht, cur, tabs, lo[PART, s], hi[PART, s])
            n_rec = _part_down(pb, tabs, s, cand, n_c, ht, cur, acc, rec, n_rec, bits)
            kind = BLOCK
        else:
            n_f, n_comb, _ = first_subtasks(pb, lo, hi, s, fs, rs)
            if marked and n_rec + n_comb > rec.shape[0]:
                need = n_rec + n_comb
                break
            cur += 1
            _local_table(ht, cur, tabs, lo[BLOCK, s], hi[BLOCK, s])
            n_rec = _block_down(pb, tabs, s, fs, n_f, rs, ht, cur, acc, rec, n_rec, bits)
            kind = PART
            s -= 1
    at[_S], at[_KIND], at[_N_REC], at[_CUR] = s, kind, n_rec, cur
    return need


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
    pb = problem(clause_bits, full, pos, thr, model)
    acc = (out, mark, np.zeros(pb.n * pb.n))
    # One hash table, big enough for every subset's entries (4 slots an entry at least).
    cap = 1024
    while cap < 4 * (tables.hi - tables.lo).max(initial=0):
        cap *= 2
    ht = (np.zeros(cap, dtype=np.int64), np.zeros(cap, dtype=np.int64))
    rec = np.empty((1024, 4), dtype=np.int64)
    at = np.zeros(4, dtype=np.int64)
    at[_S], at[_KIND] = (1 << pb.n) - 1, PART
    scr = scratch(pb.n, full.shape[0])
    while (need := _descend(tables, pb, acc, rec, ht, scr, at)) > 0:
        bigger = np.empty((max(need, 2 * rec.shape[0]), 4), dtype=np.int64)
        bigger[:at[_N_REC]] = rec[:at[_N_REC]]
        rec = bigger
    marg, rec = acc[2], rec[:at[_N_REC]]
    order = np.argsort(rec[:, 0], kind="stable")
    rec = rec[order]
    rec_start = np.searchsorted(rec[:, 0], np.arange(len(tables.weight) + 1)).astype(np.int64)
    return marg, rec_start, rec

