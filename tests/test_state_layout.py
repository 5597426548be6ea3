"""The hypothesis row [tau | W1 | parent]: its blocks, in Python and in compiled code."""

import numpy as np
import pytest
from numba import njit

from bsi_sklearn.model.priors import enumerate_structures, n_orders_of
from bsi_sklearn.model.state_layout import (
    join_state,
    max_conjuncts,
    parent_offset,
    split_state,
    split_states,
    state_width,
    w1_offset,
)

SIZES = [(0, 0), (0, 3), (2, 0), (1, 1), (3, 4)]


@pytest.mark.parametrize("n_g, n", SIZES)
def test_split_undoes_join(n_g, n):
    rng = np.random.default_rng(n_g * 10 + n)
    tau, w1 = rng.integers(0, 2, n_g), rng.integers(0, 2, n)
    parent = rng.integers(-1, max(n, 1), n)
    row = join_state(tau, w1, parent)
    assert row.shape == (state_width(n_g, n),)
    got = split_state(row, n_g, n)
    for block, want in zip(got, (tau, w1, parent)):
        np.testing.assert_array_equal(block, want)
        assert block.base is row  # views: writing a block writes the row
    if n:
        assert row[w1_offset(n_g)] == w1[0] and row[parent_offset(n_g, n)] == parent[0]


@pytest.mark.parametrize("n_g, n", SIZES)
def test_rows_split_as_each_row(n_g, n):
    rows = np.arange(3 * state_width(n_g, n)).reshape(3, -1)
    blocks = split_states(rows, n_g, n)
    for r in range(3):
        for block, one in zip(blocks, split_state(rows[r], n_g, n)):
            np.testing.assert_array_equal(block[r], one)


@njit
def _compiled(row, n_g, n):
    tau, w1, parent = split_state(row, n_g, n)
    return state_width(n_g, n), tau.sum(), w1.sum(), parent.sum(), max_conjuncts(n_g, n)


def test_compiled_code_reads_the_same_layout():
    n_g, n = 2, 3
    row = join_state([1, 1], [1, 0, 1], [-1, 0, 0])
    tau, w1, parent = split_state(row, n_g, n)
    assert _compiled(row, n_g, n) == (len(row), tau.sum(), w1.sum(), parent.sum(),
                                      max_conjuncts(n_g, n))


@pytest.mark.parametrize("n", range(5))
def test_max_conjuncts_is_reached_by_a_chain(n):
    # Forests are the widest support: the most orders of any of its structures.
    most = max(n_orders_of(p) for p in enumerate_structures("forest", n))
    assert max_conjuncts(2, n) == 2 + n + most
