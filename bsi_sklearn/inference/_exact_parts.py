"""The parts of the exact enumeration: bitset tables and their groups.

A hypothesis is an order structure, a subset of the global candidates and a subset of the
eventual subtasks. Each part is described by the bitset of demonstrations it satisfies, its
number of conjuncts and its log prior. The exact posterior runs over *groups* of parts that
share ``(bitset, size)`` (:mod:`bsi_sklearn.inference._grouping`): order structures are generated
depth-first and grouped as they come, without an array over all of them; the two subsets are
grouped, then combined into groups of (global subset, eventual subset) pairs.
"""

from typing import NamedTuple

import numpy as np
from numba import njit

from bsi_sklearn.clauses import popcount
from bsi_sklearn.inference._grouping import (
    Groups,
    add_weight,
    group_rows,
    insert,
    new_table,
    with_room,
)
from bsi_sklearn.priors import log_prior_subset, next_assignment, structure_log_prior

__all__ = ["PartTable", "SubsetGroups", "Pruning", "StructureWalk", "subset_table", "new_walk",
           "next_kept_structure", "ancestor_masks", "group_structures", "group_subsets"]


class PartTable(NamedTuple):
    """One part of the hypotheses, item by item (order structures or subsets)."""

    bits: np.ndarray   # (n_items, n_words) uint64: the demonstrations each item satisfies
    size: np.ndarray   # (n_items,) int64: its number of conjuncts
    lp: np.ndarray     # (n_items,) float64: its log prior


class SubsetGroups(NamedTuple):
    """Groups of (global subset, eventual subset) pairs, with the way back to their members."""

    groups: Groups          # the pair groups ("te" groups)
    pair_start: np.ndarray  # (G + 1,) int64: CSR offsets into pair_t / pair_e
    pair_t: np.ndarray      # global-subset group of each member pair of groups
    pair_e: np.ndarray      # eventual-subset group of each member pair of groups
    t_groups: Groups
    t_start: np.ndarray     # CSR offsets into t_items, by global-subset group
    t_items: np.ndarray     # global subsets (bit masks over the candidates), by group
    t_lp: np.ndarray        # log prior of every global subset, by mask
    e_groups: Groups
    e_start: np.ndarray
    e_items: np.ndarray
    e_lp: np.ndarray
    pair_lw: np.ndarray     # log prior weight of each member pair of groups


def subset_table(clause_bits, first_clause, n_items, p, full):
    """Bitset, size and log prior of every subset (bit mask) of ``n_items`` clauses.

    Plain numpy, one doubling step per clause (it spares a compilation on the first fit).
    """
    bits = np.empty((1 << n_items, clause_bits.shape[1]), dtype=np.uint64)
    size = np.zeros(1 << n_items, dtype=np.int64)
    bits[0] = full
    for i in range(n_items):
        half = 1 << i  # masks [half, 2 half) add clause i to masks [0, half)
        bits[half:2 * half] = bits[:half] & clause_bits[first_clause + i]
        size[half:2 * half] = size[:half] + 1
    lp = np.array([log_prior_subset.py_func(k, n_items, p) for k in range(n_items + 1)])
    return PartTable(bits, size, lp[size])


class Pruning(NamedTuple):
    """Which partial structures the walk abandons.

    A partial structure's known orders only shrink the set of demonstrations it satisfies, so
    ``P`` (the acceptable demonstrations its orders satisfy so far) bounds every completion.
    The walk skips a partial structure when ``P < min_pos`` or ``bound[P] < cut``.
    """

    clause_bits: np.ndarray  # (n_clauses, n_words) uint64
    pos: np.ndarray          # (n_words,) acceptable demonstrations
    bound: np.ndarray        # (n_pos + 1,) non-decreasing bound on the log likelihood
    cut: float
    min_pos: int
    max_visits: int          # the walk stops after this many structures (a work budget)


class StructureWalk(NamedTuple):
    """State of the depth-first walk over order structures (see :func:`next_kept_structure`)."""

    parent: np.ndarray     # (n,) the current (partial) structure
    n_children: np.ndarray
    state: np.ndarray      # (4,) for priors.next_assignment
    bits: np.ndarray       # (n + 1, n_words): AND of the orders known after each level
    size: np.ndarray       # (n + 1,): number of those orders
    above: np.ndarray      # (n,) scratch: new ancestors
    below: np.ndarray      # (n,) scratch: new descendants


@njit(cache=True, nogil=True)
def new_walk(n, full):
    """A walk at its start; ``full`` is the all-demonstrations bitset."""
    bits = np.empty((n + 1, full.shape[0]), dtype=np.uint64)
    for w in range(full.shape[0]):  # not bits[0] = full: see _grouping._grown
        bits[0, w] = full[w]
    return StructureWalk(np.full(n, -2, dtype=np.int64), np.zeros(n, dtype=np.int64),
                         np.zeros(4, dtype=np.int64), bits, np.zeros(n + 1, dtype=np.int64),
                         np.empty(max(n, 1), dtype=np.int64), np.empty(max(n, 1), dtype=np.int64))


@njit(cache=True, nogil=True)
def _add_orders(wk, v, clause_bits, base):
    # Node v just got its parent: the orders that became known are (a, d) for every new
    # ancestor a (the parent's chain up to the first node not placed yet, inclusive) and every
    # d in {v} and the placed nodes whose chain stopped at v.
    n = wk.parent.shape[0]
    n_above = 0
    a = wk.parent[v]
    while a >= 0:
        wk.above[n_above] = a
        n_above += 1
        if a > v:
            break
        a = wk.parent[a]
    n_below = 1
    wk.below[0] = v
    for d in range(v):
        x = wk.parent[d]
        while 0 <= x < v:
            x = wk.parent[x]
        if x == v:
            wk.below[n_below] = d
            n_below += 1
    n_words = wk.bits.shape[1]
    for w in range(n_words):
        wk.bits[v + 1, w] = wk.bits[v, w]
    for i in range(n_above):
        for j in range(n_below):
            c = base + wk.above[i] * n + wk.below[j]
            for w in range(n_words):
                wk.bits[v + 1, w] &= clause_bits[c, w]
    wk.size[v + 1] = wk.size[v] + n_above * n_below


@njit(cache=True, nogil=True)
def next_kept_structure(wk, model, rule):
    """Advance the walk to the next order structure the pruning rule keeps.

    Returns False when there is none left; otherwise the structure is in ``wk.parent``, its
    bitset in ``wk.bits[n]`` and its number of orders in ``wk.size[n]``.
    """
    n = wk.parent.shape[0]
    if n == 0:
        done = wk.state[2] == 1
        wk.state[2] = 1
        return not done
    base = model.n_g + n
    descend = True
    while True:
        v = next_assignment(wk.parent, wk.n_children, wk.state, model.prior, descend)
        if v < 0:
            return False
        _add_orders(wk, v, rule.clause_bits, base)
        p = 0
        for w in range(rule.pos.shape[0]):
            p += popcount(wk.bits[v + 1, w] & rule.pos[w])
        if p < rule.min_pos or rule.bound[p] < rule.cut:
            descend = False
            continue
        if v == n - 1:
            return True
        descend = True


@njit(cache=True, nogil=True)
def ancestor_masks(parent, anc):
    """Each subtask's ancestors as a bit mask, into ``anc``; returns the number of orders."""
    size = 0
    for v in range(parent.shape[0]):
        m = 0
        a = parent[v]
        while a >= 0:
            m |= 1 << a
            size += 1
            a = parent[a]
        anc[v] = m
    return size


@njit(cache=True, nogil=True)
def _fill_groups(wk, model, rule, table, weight, best, members, ref, scratch, visits):
    # Group kept structures until the walk ends (returns 1), the table is full (0) or more
    # than rule.max_visits structures were seen (2); the walk resumes at the next call
    # (growing arrays inside this loop would make numba reload them at every step).
    n = model.n
    room = table.bits.shape[0]
    while table.count[0] < room:
        if not next_kept_structure(wk, model, rule):
            return 1
        visits[0] += 1
        if visits[0] > rule.max_visits:
            return 2
        lp = structure_log_prior(wk.parent, model, scratch)
        if lp == -np.inf:
            continue
        g = insert(table, wk.bits[n], wk.size[n])
        members[g] += 1
        ref[0] = add_weight(weight, best, ref[0], g, lp, lp)
    return 0


@njit(cache=True, nogil=True)
def group_structures(full, model, rule):
    """Walk the order structures the rule keeps and group them by ``(bitset, size)``.

    Returns ``(table, groups, members, n_visited, complete)``: the hash table (to find a
    structure's group again), the groups with their summed prior weights, each group's number
    of structures, how many structures were walked, and False when the walk stopped at
    ``rule.max_visits``. Memory grows with the number of groups only.
    """
    n = model.n
    table = new_table(full.shape[0], 4096)
    weight = np.zeros(table.bits.shape[0])
    best = np.full(table.bits.shape[0], -np.inf)
    members = np.zeros(table.bits.shape[0], dtype=np.int64)
    ref = np.full(1, -np.inf)
    visits = np.zeros(1, dtype=np.int64)
    wk = new_walk(n, full)
    scratch = np.zeros(n, dtype=np.int64)
    while True:
        code = _fill_groups(wk, model, rule, table, weight, best, members, ref, scratch, visits)
        if code:
            break
        table = with_room(table)
        room = table.bits.shape[0]
        w2 = np.zeros(room)
        b2 = np.full(room, -np.inf)
        m2 = np.zeros(room, dtype=np.int64)
        for g in range(weight.shape[0]):  # loops, not slice copies (see _grouping._grown)
            w2[g] = weight[g]
            b2[g] = best[g]
            m2[g] = members[g]
        weight, best, members = w2, b2, m2
    k = table.count[0]
    groups = Groups(table.bits[:k].copy(), table.size[:k].copy(), weight[:k].copy(), ref[0],
                    best[:k].copy())
    return table, groups, members[:k].copy(), visits[0], code == 1


def _members(gid, n_groups):
    # CSR lists of the items of each group, items in increasing order.
    ok = np.flatnonzero(gid >= 0)
    order = ok[np.argsort(gid[ok], kind="stable")]
    start = np.zeros(n_groups + 1, dtype=np.int64)
    np.add.at(start, gid[ok] + 1, 1)
    return np.cumsum(start), order.astype(np.int64)


def group_subsets(clause_bits, full, model):
    """Group the global subsets, the eventual subsets, then pairs of their groups."""
    n_g, n = model.n_g, model.n
    t_tab = subset_table(clause_bits, 0, n_g, model.p_global, full)
    e_tab = subset_table(clause_bits, n_g, n, model.p_eventual, full)
    t_gid, tg = group_rows(t_tab.bits, t_tab.size, t_tab.lp)
    e_gid, eg = group_rows(e_tab.bits, e_tab.size, e_tab.lp)
    t_start, t_items = _members(t_gid, len(tg.size))
    e_start, e_items = _members(e_gid, len(eg.size))
    # Pairs of groups: every (global group, eventual group), then grouped again.
    a, b = np.divmod(np.arange(len(tg.size) * len(eg.size)), len(eg.size))
    with np.errstate(divide="ignore"):
        lw = np.log(tg.weight)[a] + tg.ref + np.log(eg.weight)[b] + eg.ref
    pair_gid, groups = group_rows(tg.bits[a] & eg.bits[b], tg.size[a] + eg.size[b], lw,
                                  tg.best[a] + eg.best[b])
    pair_start, pairs = _members(pair_gid, len(groups.size))
    return SubsetGroups(groups, pair_start, a[pairs], b[pairs], tg, t_start, t_items, t_tab.lp,
                        eg, e_start, e_items, e_tab.lp, lw[pairs])
