"""The layout of a hypothesis as one row of integers: ``[tau | W1 | parent]``.

For ``n_g`` global candidates and ``n`` subtasks a row has :func:`state_width` entries:

- ``j``            : ``tau_j``, whether ``G(tau_j)`` is a conjunct
- ``n_g + w``      : ``W1_w``, whether ``pi_w -> F(omega_w)`` is a conjunct
- ``n_g + n + w``  : the parent of subtask ``w`` in the order structure (-1 for a root)

The sampler's recorded states, the chains' starting point, the local search's rows and the
monitor's packed roles (``[global columns | subtask columns | condition columns]``, the same
three blocks) are laid out so. This module is the one place that layout is written; like the
clause layout of :mod:`bsi_sklearn.model.clauses`, its functions are plain Python that numba
kernels may call too (``register_jitable``: inlined when compiled).
"""

import numpy as np
from numba.extending import register_jitable

__all__ = ["state_width", "w1_offset", "parent_offset", "split_state", "split_states",
           "join_state", "max_conjuncts"]


@register_jitable
def state_width(n_g, n):
    """Number of entries of a row: one per global candidate, two per subtask."""
    return n_g + 2 * n


@register_jitable
def w1_offset(n_g):
    """Entry of ``W1_0`` (``tau_j`` is entry ``j``)."""
    return n_g


@register_jitable
def parent_offset(n_g, n):
    """Entry of the parent of subtask 0."""
    return n_g + n


@register_jitable
def split_state(row, n_g, n):
    """``(tau, w1, parent)``: views of one row's three blocks (no copy)."""
    return (row[:w1_offset(n_g)], row[w1_offset(n_g):parent_offset(n_g, n)],
            row[parent_offset(n_g, n):state_width(n_g, n)])


def split_states(rows, n_g, n):
    """``(tau, w1, parent)``: views of the three blocks of every row of ``rows`` (2-D)."""
    return (rows[:, :w1_offset(n_g)], rows[:, w1_offset(n_g):parent_offset(n_g, n)],
            rows[:, parent_offset(n_g, n):state_width(n_g, n)])


def join_state(tau, w1, parent, dtype=np.int64):
    """One row from its three blocks.

    Examples
    --------
    >>> join_state([1, 0], [1], [-1]).tolist()
    [1, 0, 1, -1]
    """
    return np.concatenate([np.asarray(tau, dtype=dtype), np.asarray(w1, dtype=dtype),
                           np.asarray(parent, dtype=dtype)])


@register_jitable
def max_conjuncts(n_g, n):
    """The most conjuncts a hypothesis has.

    Every ``G`` and ``F`` clause, and the ``n (n - 1) / 2`` orders of one chain through every
    subtask (the most ancestor -> descendant pairs of a forest).
    """
    return n_g + n + n * (n - 1) // 2
