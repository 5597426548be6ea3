"""The parts of the exact enumeration: bitset tables and their groups.

A hypothesis is an order structure, a subset of the global candidates and a subset of the
eventual subtasks. Each part is described by the bitset of demonstrations it satisfies, its
number of conjuncts and its log prior. The exact posterior runs over *groups* of parts that
share ``(bitset, size)`` (:mod:`bsi_sklearn.inference._grouping`): the two subsets are grouped
here, then combined into groups of (global subset, eventual subset) pairs; the order structures
are counted in the tables of :mod:`bsi_sklearn.inference._structures` and their whole
structures grouped here.
"""

import math
from typing import NamedTuple

import numpy as np

from bsi_sklearn.inference._grouping import Groups, group_rows
from bsi_sklearn.inference._structures import whole_kind
from bsi_sklearn.model.clauses import clause_index_eventual
from bsi_sklearn.model.priors import log_prior_subset, whole_structure_log_factor

__all__ = ["PartTable", "SubsetGroups", "subset_table", "group_subsets", "top_entries",
           "structure_groups", "subset_items", "ROW_COST", "PAIR_COST"]

#: Work units (evaluations of a pair of groups, about 5-10 ns) of one row of a subset table
#: (built, then grouped by sorting) and of one pair of (global, eventual) subset groups.
ROW_COST = 20
PAIR_COST = 20


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


def subset_table(clause_bits, first_clause, n_items, p, full, pat_in=(), pat_out=()):
    """Bitset, size and log prior of every subset (bit mask) of ``n_items`` clauses.

    Plain numpy, one doubling step per clause (it spares a compilation on the first fit).
    The last ``len(pat_in)`` items are pattern clauses (DESIGN §12), each included with its
    own log probabilities ``pat_in`` / ``pat_out``; the others are SampleSubset(p).
    """
    n_pat = len(pat_in)
    n_plain = n_items - n_pat
    bits = np.empty((1 << n_items, clause_bits.shape[1]), dtype=np.uint64)
    size = np.zeros(1 << n_items, dtype=np.int64)
    bits[0] = full
    for i in range(n_items):
        half = 1 << i  # masks [half, 2 half) add clause i to masks [0, half)
        bits[half:2 * half] = bits[:half] & clause_bits[first_clause + i]
        size[half:2 * half] = size[:half] + 1
    lp = np.array([log_prior_subset.py_func(k, n_plain, p) for k in range(n_plain + 1)])
    if not n_pat:
        return PartTable(bits, size, lp[size])
    # The plain clauses are the low n_plain bits of a mask; each pattern clause one bit above.
    lp_pat = np.full(1 << n_items, float(np.sum(pat_out)))
    for i in range(n_pat):
        half = 1 << (n_plain + i)
        lp_pat[half:2 * half] = lp_pat[:half] + (pat_in[i] - pat_out[i])
    lo = np.arange(1 << n_items) & ((1 << n_plain) - 1)
    return PartTable(bits, size, lp[size[lo]] + lp_pat)


def _pow2(k):
    # 2**k as a float, infinite past the floats (hundreds of pattern clauses are global slots)
    return math.ldexp(1.0, k) if k < 1024 else math.inf


def _members(gid, n_groups):
    # CSR lists of the items of each group, items in increasing order.
    ok = np.flatnonzero(gid >= 0)
    order = ok[np.argsort(gid[ok], kind="stable")]
    start = np.zeros(n_groups + 1, dtype=np.int64)
    np.add.at(start, gid[ok] + 1, 1)
    return np.cumsum(start), order.astype(np.int64)


def group_subsets(clause_bits, full, model, spend=None, allocate=None):
    """Group the global subsets, the eventual subsets, then pairs of their groups.

    ``spend(work, what)``, when given, is called before each table is allocated (work in the
    units of :data:`ROW_COST`, :data:`PAIR_COST`), and ``allocate(nbytes, what)`` with its
    memory; either raises to stop.
    """
    n_g, n = model.n_g, model.n
    n_words = clause_bits.shape[1]
    what = f"the subset tables (2**{n_g} + 2**{n} rows)"
    if spend is not None:
        spend(ROW_COST * (_pow2(n_g) + _pow2(n)), what)
    if allocate is not None:  # a row, and as much twice again while it is grouped
        allocate(3.0 * (8 * n_words + 24) * (_pow2(n_g) + _pow2(n)), what)
    t_tab = subset_table(clause_bits, 0, n_g, model.p_global, full, model.pat_in,
                         model.pat_out)
    e_tab = subset_table(clause_bits, clause_index_eventual(0, n_g), n, model.p_eventual, full)
    t_gid, tg = group_rows(t_tab.bits, t_tab.size, t_tab.lp)
    e_gid, eg = group_rows(e_tab.bits, e_tab.size, e_tab.lp)
    t_start, t_items = _members(t_gid, len(tg.size))
    e_start, e_items = _members(e_gid, len(eg.size))
    # Pairs of groups: every (global group, eventual group), then grouped again.
    what = f"{len(tg.size):,} x {len(eg.size):,} pairs of subset groups"
    if spend is not None:
        spend(PAIR_COST * float(len(tg.size)) * len(eg.size), what)
    if allocate is not None:
        allocate(2.0 * (8 * n_words + 48) * len(tg.size) * len(eg.size), what)
    a, b = np.divmod(np.arange(len(tg.size) * len(eg.size)), len(eg.size))
    with np.errstate(divide="ignore"):
        lw = np.log(tg.weight)[a] + tg.ref + np.log(eg.weight)[b] + eg.ref
    pair_gid, groups = group_rows(tg.bits[a] & eg.bits[b], tg.size[a] + eg.size[b], lw,
                                  tg.best[a] + eg.best[b])
    pair_start, pairs = _members(pair_gid, len(groups.size))
    return SubsetGroups(groups, pair_start, a[pairs], b[pairs], tg, t_start, t_items, t_tab.lp,
                        eg, e_start, e_items, e_tab.lp, lw[pairs])


def subset_items(subsets):
    """How many (global subset, eventual subset) pairs each subset-pair group holds (float)."""
    n_in = np.diff(subsets.t_start).astype(float)[subsets.pair_t] * \
        np.diff(subsets.e_start).astype(float)[subsets.pair_e]
    return np.add.reduceat(n_in, subsets.pair_start[:-1]) if len(n_in) else n_in


def top_entries(tables, model):
    """The entries of the structure tables that hold whole structures.

    Returns ``(ids, log_weight, log_best)``: the entries on the whole set of subtasks, each
    entry's summed prior weight and its most probable member's log prior, both absolute (the
    prior's factor of the whole structure, e.g. Prior 2's by number of chains, added).
    """
    n = model.n
    whole = (1 << n) - 1
    kind = whole_kind(model)
    ids = np.arange(tables.lo[kind, whole], tables.hi[kind, whole])
    if n == 0:
        top = np.zeros(len(ids))
    else:
        # The number of blocks of each structure (counted for chains; one block: one chain).
        aux = tables.aux[ids] if kind == 1 else np.ones(len(ids), dtype=np.int64)
        top = whole_structure_log_factor(model, aux)
    with np.errstate(divide="ignore"):
        lw = np.log(tables.weight[ids]) + tables.ref[kind, whole] + top
    return ids, lw, tables.best[ids] + top


def structure_groups(tables, model):
    """The whole structures grouped by (bitset, orders), as the passes take them.

    Returns ``(groups, members, gid)``: the groups (summed prior weights, most probable
    member), each group's number of structures (float: it may pass 2**63) and each entry of
    :func:`top_entries`' group (-1 for an entry of prior weight 0).
    """
    ids, lw, best = top_entries(tables, model)
    if len(ids) == 0:
        n_words = tables.bits.shape[1]
        return (Groups(np.empty((0, n_words), np.uint64), np.empty(0, np.int64), np.empty(0),
                       -np.inf, np.empty(0)), np.empty(0), np.empty(0, np.int64))
    gid, groups = group_rows(tables.bits[ids], tables.size[ids], lw, best)
    ok = gid >= 0
    members = np.bincount(gid[ok], weights=tables.count[ids][ok], minlength=len(groups.size))
    return groups, members, gid
