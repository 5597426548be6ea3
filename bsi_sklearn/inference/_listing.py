"""The listing of the kept hypotheses of the grouped exact enumeration.

The walk down the structure tables (:mod:`bsi_sklearn.inference._structure_walk`) records the
derivations of the structure groups that may hold a hypothesis above the keep threshold;
:func:`list_hypotheses` rebuilds every structure of those groups from them, depth first, and
pairs it with the global and eventual subsets that keep it above the threshold (a min-heap keeps
the most probable when there are more than the room given).
"""

from typing import NamedTuple

import numpy as np
from numba import njit

from bsi_sklearn._jit import helper
from bsi_sklearn.model.priors import structure_log_prior

__all__ = ["Listing", "Members", "members", "walk_scratch", "list_hypotheses"]


@helper
def _heap_add(heap_lp, heap_slot, size, value, slot):
    # Min-heap of (log posterior, slot of out_*): the least probable kept hypothesis on top.
    i = size
    heap_lp[i] = value
    heap_slot[i] = slot
    while i > 0:
        up = (i - 1) // 2
        if heap_lp[up] <= heap_lp[i]:
            break
        heap_lp[i], heap_lp[up] = heap_lp[up], heap_lp[i]
        heap_slot[i], heap_slot[up] = heap_slot[up], heap_slot[i]
        i = up


@helper
def _heap_replace_top(heap_lp, heap_slot, size, value):
    # The top's slot now holds a more probable hypothesis: restore the heap.
    heap_lp[0] = value
    i = 0
    while True:
        small = i
        for child in (2 * i + 1, 2 * i + 2):
            if child < size and heap_lp[child] < heap_lp[small]:
                small = child
        if small == i:
            break
        heap_lp[i], heap_lp[small] = heap_lp[small], heap_lp[i]
        heap_slot[i], heap_slot[small] = heap_slot[small], heap_slot[i]
        i = small


@helper
def _put(out_par, out_idx, out_lp, slot, parent, t, e, value):
    for v in range(parent.shape[0]):
        out_par[slot, v] = parent[v]
    out_idx[slot, 0] = t
    out_idx[slot, 1] = e
    out_lp[slot] = value


class Listing(NamedTuple):
    """What the listing of the kept hypotheses needs (see :func:`list_hypotheses`)."""

    rec_start: np.ndarray   # (E + 1,) derivations of table entry e: rec[rec_start[e]:...]
    rec: np.ndarray         # (R, 4) rows (entry, a, b, f) (see _structure_walk.descend)
    targets: np.ndarray     # (T,) whole-set entries whose structures are listed
    group: np.ndarray       # (T,) each target's structure group (sorted StructureSide order)
    pass_start: np.ndarray  # (G + 1,) CSR by structure group: the subset-pair groups that
    pass_h: np.ndarray      # may reach keep with it (SubsetSide positions)
    pass_ll: np.ndarray     # and the pair's log likelihood
    h_order: np.ndarray     # SubsetSide position -> subset-pair group id
    keep: float             # absolute log posterior (unnormalised) a kept hypothesis reaches


@helper
def _expand(rec, k, attach, parent, pend_e, pend_a, n_pend):
    # Apply derivation k to an entry hanging under `attach`: a block puts its first subtask
    # (or root) f under attach and hangs the rest under f; a structure hangs its block and
    # its rest under attach. The empty structure (entry 0) needs nothing.
    f = rec[k, 3]
    if f >= 0:
        parent[f] = attach
        if rec[k, 1] != 0:
            pend_e[n_pend] = rec[k, 1]
            pend_a[n_pend] = f
            n_pend += 1
        return n_pend
    if rec[k, 2] != 0:
        pend_e[n_pend] = rec[k, 2]
        pend_a[n_pend] = attach
        n_pend += 1
    pend_e[n_pend] = rec[k, 1]
    pend_a[n_pend] = attach
    return n_pend + 1


class Members(NamedTuple):
    """What the listing reads of the subset groups (``_exact_parts.SubsetGroups``)."""

    pair_start: np.ndarray  # CSR offsets into pair_t / pair_e, by subset-pair group
    pair_t: np.ndarray      # global-subset group of each member pair of groups
    pair_e: np.ndarray      # eventual-subset group of each member pair of groups
    t_best: np.ndarray      # largest member log prior of each global-subset group
    e_best: np.ndarray      # and of each eventual-subset group
    t_start: np.ndarray     # CSR offsets into t_items, by global-subset group
    t_items: np.ndarray     # global subsets (bit masks), by group
    t_lp: np.ndarray        # log prior of every global subset, by mask
    e_start: np.ndarray
    e_items: np.ndarray
    e_lp: np.ndarray


def members(subsets):
    """The :class:`Members` of ``_exact_parts.SubsetGroups``."""
    return Members(subsets.pair_start, subsets.pair_t, subsets.pair_e, subsets.t_groups.best,
                   subsets.e_groups.best, subsets.t_start, subsets.t_items, subsets.t_lp,
                   subsets.e_start, subsets.e_items, subsets.e_lp)


class _Walk(NamedTuple):
    # The scratch of list_hypotheses' depth-first walk (allocated by Python, see walk_scratch).
    parent: np.ndarray  # (n,) int64
    scratch: np.ndarray  # (n,) int64
    pend_e: np.ndarray  # (n + 1,) int64: entries still to expand, and where they hang
    pend_a: np.ndarray
    fr_e: np.ndarray    # (2 n + 2,) int64: the frames of the walk
    fr_a: np.ndarray
    fr_k: np.ndarray
    fr_n: np.ndarray
    fr_pe: np.ndarray   # (2 n + 2, n + 1) int64
    fr_pa: np.ndarray
    heap_lp: np.ndarray  # (room,) float64: the min-heap of the kept hypotheses
    heap_slot: np.ndarray  # (room,) int64


def walk_scratch(n, room):
    """The scratch arrays of :func:`list_hypotheses` for ``n`` subtasks, ``room`` hypotheses."""
    depth = 2 * n + 2
    return _Walk(np.full(n, -1, dtype=np.int64), np.zeros(n, dtype=np.int64),
                 *[np.empty(n + 1, dtype=np.int64) for _ in range(2)],
                 *[np.empty(depth, dtype=np.int64) for _ in range(4)],
                 *[np.empty((depth, n + 1), dtype=np.int64) for _ in range(2)],
                 np.empty(room), np.empty(room, dtype=np.int64))


@njit(cache=True, nogil=True)
def list_hypotheses(model, h_best, subsets, ls, out_par, out_idx, out_lp, wk):
    """Enumerate the structures of the target entries and list their kept hypotheses.

    Every structure of a target is rebuilt from its derivations (a depth-first walk with a
    stack of the entries still to expand); the hypotheses at or above ``ls.keep`` are written
    to ``out_*`` (structure, [global mask, eventual mask], unnormalised log posterior), in no
    particular order; when there are more than they have room for, a min-heap keeps the most
    probable. Returns the number of hypotheses at or above ``ls.keep``, which may exceed the
    room in ``out_*``. ``h_best``: ``SubsetSide.best``; ``subsets``: :class:`Members`; ``wk``:
    :func:`walk_scratch`.
    """
    parent, scratch, pend_e, pend_a = wk.parent, wk.scratch, wk.pend_e, wk.pend_a
    fr_e, fr_a, fr_k, fr_n, fr_pe, fr_pa = wk.fr_e, wk.fr_a, wk.fr_k, wk.fr_n, wk.fr_pe, wk.fr_pa
    heap_lp, heap_slot = wk.heap_lp, wk.heap_slot
    k = np.int64(0)
    for ti in range(ls.targets.shape[0]):
        g = ls.group[ti]
        n_pend = 0
        if ls.targets[ti] != 0:
            pend_e[0] = ls.targets[ti]
            pend_a[0] = -1
            n_pend = 1
        d = 0
        down = True
        while True:
            if down:
                if n_pend > 0:
                    n_pend -= 1
                    fr_e[d] = pend_e[n_pend]
                    fr_a[d] = pend_a[n_pend]
                    fr_n[d] = n_pend
                    for i in range(n_pend):
                        fr_pe[d, i] = pend_e[i]
                        fr_pa[d, i] = pend_a[i]
                    fr_k[d] = ls.rec_start[fr_e[d]]
                    n_pend = _expand(ls.rec, fr_k[d], fr_a[d], parent, pend_e, pend_a, n_pend)
                    d += 1
                    continue
                lp = structure_log_prior(parent, model, scratch)
                k = _list_one(parent, lp, g, h_best, subsets, ls, k, out_par, out_idx, out_lp,
                              heap_lp, heap_slot)
                down = False
                continue
            if d == 0:
                break
            d -= 1
            nxt = fr_k[d] + 1
            if nxt == ls.rec_start[fr_e[d] + 1]:
                continue
            fr_k[d] = nxt
            n_pend = fr_n[d]
            for i in range(n_pend):
                pend_e[i] = fr_pe[d, i]
                pend_a[i] = fr_pa[d, i]
            n_pend = _expand(ls.rec, nxt, fr_a[d], parent, pend_e, pend_a, n_pend)
            d += 1
            down = True
    return k


@helper
def _list_one(parent, lp, g, h_best, subsets, ls, k, out_par, out_idx, out_lp, heap_lp,
              heap_slot):
    # The hypotheses of one structure (log prior lp, structure group g) at or above keep.
    cap = out_lp.shape[0]
    for j in range(ls.pass_start[g], ls.pass_start[g + 1]):
        hi = ls.pass_h[j]
        ll = ls.pass_ll[j]
        floor = ls.keep
        if k >= cap and heap_lp[0] > floor:
            floor = heap_lp[0]  # the heap is full: beat its least probable
        need = floor - lp - ll  # a member's log prior must reach this
        if h_best[hi] < need:
            continue
        h = ls.h_order[hi]
        for q in range(subsets.pair_start[h], subsets.pair_start[h + 1]):
            gt = subsets.pair_t[q]
            ge = subsets.pair_e[q]
            if subsets.t_best[gt] + subsets.e_best[ge] < need:
                continue
            for it in range(subsets.t_start[gt], subsets.t_start[gt + 1]):
                t = subsets.t_items[it]
                for ie in range(subsets.e_start[ge], subsets.e_start[ge + 1]):
                    e = subsets.e_items[ie]
                    lp_te = subsets.t_lp[t] + subsets.e_lp[e]
                    if lp_te < need:
                        continue
                    value = lp + lp_te + ll
                    k += 1
                    if k <= cap:
                        _put(out_par, out_idx, out_lp, k - 1, parent, t, e, value)
                        _heap_add(heap_lp, heap_slot, k - 1, value, k - 1)
                    elif value > heap_lp[0]:
                        _put(out_par, out_idx, out_lp, heap_slot[0], parent, t, e, value)
                        _heap_replace_top(heap_lp, heap_slot, cap, value)
    return k
