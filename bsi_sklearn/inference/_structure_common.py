"""What both passes over the order-structure tables share.

The inside pass (:mod:`bsi_sklearn.inference._structures`) and the walk back down
(:mod:`bsi_sklearn.inference._structure_walk`) read the same problem bundle, write the same
scratch arrays, and take the same steps over the subsets of subtasks: the blocks that may hold
a subset's lowest subtask beside a structure on the rest (:func:`candidates`), the subtasks
that may come first in a block (:func:`first_subtasks`), and the hash probe that finds an
entry of a subset's table by its key (:func:`find`).
"""

from typing import NamedTuple

import numpy as np
from numba import njit

from bsi_sklearn._jit import helper
from bsi_sklearn.model.clauses import clause_index_order, popcount
from bsi_sklearn.model.priors import is_forest, structures_are_sets

__all__ = ["BLOCK", "PART", "COMBO_COST", "STEP_COST", "ENTRY_COST", "whole_kind",
           "problem", "scratch", "n_bits", "and_pop", "find", "append_block", "candidates",
           "first_subtasks"]

#: The two kinds of table entries: blocks (one chain, one tree) and whole structures.
BLOCK = 0
PART = 1
#: Work units (evaluations of a pair of groups, about 5-10 ns) of one combination of two table
#: entries (an AND, a popcount, a hash probe), of one step over subsets or subtasks, and of a
#: new entry (its time, and as much again for its memory: about 60 bytes, so that the work
#: budget bounds the memory too).
COMBO_COST = 4
STEP_COST = 1
ENTRY_COST = 32


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
    return PART if structures_are_sets(model) or model.n == 0 else BLOCK


def problem(clause_bits, full, pos, thr, model):
    """The bundle both passes over the tables read."""
    n = model.n
    chains = not is_forest(model)
    factor = np.zeros(n + 2) if chains else np.asarray(model.forest_g, dtype=np.float64)
    return _Problem(clause_bits, clause_index_order(0, 0, model.n_g, n), n, full, pos, int(thr),
                    factor, 1 if chains else 0, BLOCK if chains else PART,
                    structures_are_sets(model))


@njit(cache=True, nogil=True, inline="always")
def n_bits(x):
    c = 0
    while x:
        x &= x - 1
        c += 1
    return c


@njit(cache=True, nogil=True, inline="always")
def _lowest(s):
    i = 0
    while not (s >> i) & 1:
        i += 1
    return i


@helper
def and_pop(a, i, b, j, out, pos):
    # out = a[i] & b[j] (rows of packed words); returns the acceptable demonstrations in it.
    p = 0
    for w in range(out.shape[0]):
        out[w] = a[i, w] & b[j, w]
        p += popcount(out[w] & pos[w])
    return p


@helper
def find(loc, stamp, cur, t_bits, t_size, t_aux, bits, size, aux):
    # Slot of the key (bits, size, aux) in the subset's own hash table, and its entry (-1:
    # absent). The table holds one subset's entries at a time (stamp == cur), so it stays in
    # cache; keys are compared through the entry arrays.
    h = np.uint64(size * 256 + aux + 1) * np.uint64(0x9E3779B97F4A7C15)
    for w in range(bits.shape[0]):
        h ^= bits[w]
        h ^= h >> np.uint64(30)
        h *= np.uint64(0xBF58476D1CE4E5B9)
        h ^= h >> np.uint64(27)
        h *= np.uint64(0x94D049BB133111EB)
        h ^= h >> np.uint64(31)
    mask = np.int64(loc.shape[0] - 1)
    i = np.int64(h & np.uint64(mask))
    while stamp[i] == cur:
        e = loc[i]
        if t_size[e] == size and t_aux[e] == aux:
            same = True
            for w in range(bits.shape[0]):
                if t_bits[e, w] != bits[w]:
                    same = False
                    break
            if same:
                return i, e
        i = (i + np.int64(1)) & mask
    return i, np.int64(-1)


@helper
def _orders_from(pb, f, rest, r):
    # r = AND of the clauses f -> u, u in rest; returns the acceptable demonstrations in r.
    for w in range(r.shape[0]):
        r[w] = pb.full[w]
    for u in range(pb.n):
        if (rest >> u) & 1:
            for w in range(r.shape[0]):
                r[w] &= pb.clause_bits[pb.base + f * pb.n + u, w]
    p = 0
    for w in range(r.shape[0]):
        p += popcount(r[w] & pb.pos[w])
    return p


@helper
def append_block(lists, s, n_sets, n):
    # lists: next subset at [s], then by lowest subtask i: head, tail, length at n_sets + (0,
    # 1, 2) * n + i (the subsets whose block tables are not empty, in increasing order).
    i = _lowest(s)
    if lists[n_sets + n + i] >= 0:
        lists[lists[n_sets + n + i]] = s
    else:
        lists[n_sets + i] = s
    lists[n_sets + n + i] = s
    lists[n_sets + 2 * n + i] += 1


@helper
def candidates(s, n, lo, hi, lists, out):
    # Blocks B (non-empty tables) holding the lowest subtask of s, with s - B non-empty too:
    # by submasks of s or through the list of blocks with that lowest subtask, whichever is
    # shorter. Returns how many (into out) and the steps taken.
    n_sets = lo.shape[1]
    i = _lowest(s)
    low = 1 << i
    rest0 = s ^ low
    k = 0
    steps = 0
    if (1 << n_bits(rest0)) <= lists[n_sets + 2 * n + i]:
        sub = rest0
        while True:
            b = sub | low
            steps += 1
            if hi[BLOCK, b] > lo[BLOCK, b] and hi[PART, s ^ b] > lo[PART, s ^ b]:
                out[k] = b
                k += 1
            if sub == 0:
                break
            sub = (sub - 1) & rest0
    else:
        b = lists[n_sets + i]
        while b >= 0:
            steps += 1
            if (b & s) == b and hi[PART, s ^ b] > lo[PART, s ^ b]:
                out[k] = b
                k += 1
            b = lists[b]
    return k, steps


@helper
def first_subtasks(pb, lo, hi, s, fs, rs):
    # The subtasks f that can come first (or be the root) in a block on s: the rest s - f
    # has a non-empty table and the orders f -> rest keep thr acceptable demonstrations.
    # Returns how many (fs, rs: f and its orders' bitset), the entries they combine and the
    # steps taken (one per subtask, and one per order clause read).
    n_f = 0
    n_comb = 0
    steps = pb.n
    for f in range(pb.n):
        c = s ^ (1 << f)
        if not (s >> f) & 1 or hi[pb.child_kind, c] == lo[pb.child_kind, c]:
            continue
        steps += pb.n
        if _orders_from(pb, f, c, rs[n_f]) < pb.thr:
            continue
        fs[n_f] = f
        n_comb += hi[pb.child_kind, c] - lo[pb.child_kind, c]
        n_f += 1
    return n_f, n_comb, steps


class _Scratch(NamedTuple):
    cand: np.ndarray  # (max(1, 2**n / 2),) int64: candidate blocks
    fs: np.ndarray    # (n,) int64: first subtasks
    rs: np.ndarray    # (n, n_words) uint64: their orders' bitsets
    bits: np.ndarray  # (n_words,) uint64


def scratch(n, n_words):
    """The scratch arrays of both passes for ``n`` subtasks and ``n_words`` words."""
    return _Scratch(np.empty(max(1, (1 << n) >> 1), dtype=np.int64),
                    np.empty(n, dtype=np.int64), np.empty((n, n_words), dtype=np.uint64),
                    np.empty(n_words, dtype=np.uint64))
