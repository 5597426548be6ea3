"""Clause truth, precomputed once per fit: one pass over a trace gives every clause's truth.

Clause layout for ``n_g`` global candidates and ``n`` subtasks (``n_clauses = n_g + n + n*n``):

- ``j``                 : ``G(tau_j)``
- ``n_g + w``           : ``pi_w -> F(omega_w)``
- ``n_g + n + a*n + b`` : ``pi_a -> (!omega_b U omega_a)``  (diagonal ``a == b`` unused, true)

This module is the one place that layout is written: :func:`n_clauses`,
:func:`clause_index_eventual` and :func:`clause_index_order` are plain Python functions that
numba kernels may call too (``register_jitable``: inlined when compiled).
"""

import numpy as np
from numba import njit, types
from numba.extending import intrinsic, register_jitable

from bsi_sklearn._compile_progress import install_notice
from bsi_sklearn.model.patterns import pattern_truth

__all__ = [
    "clause_index_eventual",
    "clause_index_order",
    "n_clauses",
    "clause_truth",
    "clause_masks",
    "clause_sums",
    "pack_rows",
    "popcount",
    "popcounts",
]

# Every fit, prediction and monitor imports this module first of the compiled ones: from here
# on, a compilation of the package's kernels longer than a second prints one line.
install_notice()


@register_jitable
def n_clauses(n_g, n):
    """Number of clause slots for ``n_g`` global candidates and ``n`` subtasks."""
    return n_g + n + n * n


@register_jitable
def clause_index_eventual(w, n_g):
    """Slot of ``pi_w -> F(omega_w)`` (the slot of ``G(tau_j)`` is ``j``)."""
    return n_g + w


@register_jitable
def clause_index_order(a, b, n_g, n):
    """Slot of ``pi_a -> (!omega_b U omega_a)`` (*a precedes b*)."""
    return n_g + n + a * n + b


def clause_truth(traces, roles, pattern_block=None):
    """Truth of every candidate clause on every demonstration.

    Parameters
    ----------
    traces : Traces
    roles : Roles
    pattern_block : ndarray of shape (n_demos, roles.n_patterns), uint8, default=None
        The pattern clauses' truth on ``traces`` when already computed (a fit's candidates
        are chosen from it: :func:`bsi_sklearn.model.pattern_candidates.pattern_candidates`);
        ``None``: computed here.

    Returns
    -------
    truth : ndarray of shape (n_demos, n_clauses), dtype uint8
        In the layout above with ``n_g = roles.n_globals + roles.n_patterns``: the pattern
        clauses (``roles.patterns``) are the global slots after the ``G`` candidates.
    """
    n_props = traces.data.shape[1]
    n_g, n = len(roles.global_idx), len(roles.subtask_idx)
    # Allocated here: a numpy allocation inside the kernel is one more compilation.
    out = np.zeros((len(traces.offsets) - 1, n_clauses(n_g, n)), dtype=np.uint8)
    _clause_truth(traces.data, traces.offsets, roles.global_idx, roles.subtask_idx,
                  roles.condition_idx, out, np.empty(n_props, dtype=np.uint8),
                  np.empty(n_props, dtype=np.int64))
    if not roles.patterns:
        return out
    # The pattern clauses are global slots n_g.. (DESIGN §12): their truth goes between the
    # G clauses and the eventual ones, one pass over the traces per template.
    patterns = pattern_block
    if patterns is None:
        patterns = np.zeros((out.shape[0], len(roles.patterns)), dtype=np.uint8)
        by_template = {}
        for k, (name, cols) in enumerate(roles.patterns):
            by_template.setdefault(name, []).append((k, cols))
        for name, items in by_template.items():
            ks = [k for k, _ in items]
            patterns[:, ks] = pattern_truth(name, traces.data, traces.offsets,
                                            [cols for _, cols in items])
    first_eventual = clause_index_eventual(0, n_g)
    return np.concatenate([out[:, :first_eventual], patterns, out[:, first_eventual:]], axis=1)


@njit(cache=True, nogil=True)
def _clause_truth(data, offsets, g_idx, s_idx, c_idx, out, always, first):
    n_demos = offsets.shape[0] - 1
    n_props = data.shape[1]
    n_g = g_idx.shape[0]
    n = s_idx.shape[0]
    for i in range(n_demos):
        start, stop = offsets[i], offsets[i + 1]
        length = stop - start
        for p in range(n_props):
            always[p] = 1
            first[p] = length  # "never"
        for t in range(length):
            row = data[start + t]
            for p in range(n_props):
                if row[p]:
                    if first[p] == length:
                        first[p] = t
                else:
                    always[p] = 0
        for j in range(n_g):
            out[i, j] = always[g_idx[j]]
        for w in range(n):
            c = c_idx[w]
            active = c < 0 or data[start, c] != 0
            done = not active or first[s_idx[w]] < length
            out[i, clause_index_eventual(w, n_g)] = 1 if done else 0
        for a in range(n):
            c = c_idx[a]
            active = c < 0 or data[start, c] != 0
            fa = first[s_idx[a]]
            for b in range(n):
                if a == b or not active:
                    out[i, clause_index_order(a, b, n_g, n)] = 1
                else:
                    # !b U a: a happens, and b does not happen strictly before the first a.
                    ok = fa < length and first[s_idx[b]] >= fa
                    out[i, clause_index_order(a, b, n_g, n)] = 1 if ok else 0


def pack_rows(bits):
    """Pack a 0/1 matrix ``(n_rows, n_cols)`` into uint64 words ``(n_rows, ceil(n_cols/64))``.

    Column ``c`` is bit ``c % 64`` of word ``c // 64`` (nonzero entries are ones). Plain numpy:
    it spares a compilation on the first fit.

    Examples
    --------
    >>> pack_rows(np.array([[1, 0, 1], [0, 1, 0]], dtype=np.uint8)).tolist()
    [[5], [2]]
    """
    bits = np.asarray(bits)
    n_rows, n_cols = bits.shape
    n_words = (n_cols + 63) // 64
    packed = np.packbits(bits != 0, axis=1, bitorder="little")
    out = np.zeros((n_rows, 8 * n_words), dtype=np.uint8)
    out[:, :packed.shape[1]] = packed
    return np.ascontiguousarray(out.view("<u8"), dtype=np.uint64)


@intrinsic
def popcount(typingctx, x):
    """Number of set bits of a uint64 (LLVM's ctpop: the hardware popcount), in numba code."""
    def codegen(context, builder, signature, args):
        return builder.ctpop(args[0])
    return types.uint64(types.uint64), codegen


def popcounts(bits, mask):
    """Number of set bits of ``bits[i] & mask`` for every row ``i`` of packed words.

    Plain numpy (it spares a compilation on the first fit); int64.

    Examples
    --------
    >>> popcounts(np.array([[7], [12]], dtype=np.uint64), np.array([5], dtype=np.uint64))
    array([2, 1])
    """
    words = np.ascontiguousarray(np.asarray(bits, dtype=np.uint64) & np.asarray(mask, np.uint64))
    if hasattr(np, "bitwise_count"):  # numpy >= 2.0
        return np.bitwise_count(words).sum(axis=1, dtype=np.int64)
    n = words.shape[0]
    return np.unpackbits(words.view(np.uint8).reshape(n, -1), axis=1).sum(axis=1,
                                                                         dtype=np.int64)


@njit(cache=True, nogil=True)
def clause_masks(structures, tau_masks, w1_masks, n_g, n):
    """Every specification's clauses as a bitset over the clause slots (the layout above).

    An order structure holds the order clause of every ancestor of each subtask, not only of
    its parent.
    """
    n_h = structures.shape[0]
    n_cl = n_clauses(n_g, n)
    n_words = (n_cl + 63) // 64
    out = np.zeros((n_h, n_words), dtype=np.uint64)
    one = np.uint64(1)
    for h in range(n_h):
        for j in range(n_g):
            if tau_masks[h, j]:
                out[h, j >> 6] |= one << np.uint64(j & 63)
        for w in range(n):
            if w1_masks[h, w]:
                c = clause_index_eventual(w, n_g)
                out[h, c >> 6] |= one << np.uint64(c & 63)
        for v in range(n):
            a = structures[h, v]
            while a >= 0:
                c = clause_index_order(a, v, n_g, n)
                out[h, c >> 6] |= one << np.uint64(c & 63)
                a = structures[h, a]
    return out


@njit(cache=True, nogil=True)
def clause_sums(masks, weights):
    """Weights summed per clause slot: with probabilities, each clause's inclusion.

    ``out[k, c]`` is the sum of ``weights[k, h]`` over the specifications ``h`` holding clause
    slot ``c`` (bit ``c`` of ``masks[h]``). ``masks`` (n_specs, n_words) uint64
    (:func:`clause_masks`), ``weights`` (n_rows, n_specs) float64; ``out`` (n_rows,
    64 n_words), the slots past the last clause 0.
    """
    n_k, n_h = weights.shape
    n_w = masks.shape[1]
    out = np.zeros((n_k, 64 * n_w))
    one = np.uint64(1)
    for h in range(n_h):
        for w in range(n_w):
            word = masks[h, w]
            while word:
                low = word & (~word + one)  # the lowest set bit
                c = 64 * w + popcount(low - one)
                for k in range(n_k):
                    out[k, c] += weights[k, h]
                word ^= low
    return out
