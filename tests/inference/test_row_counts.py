"""The bitset counts of the rows a hypothesis satisfies, against the row-by-row sums."""

import numpy as np
import pytest
from numba import njit

from bsi_sklearn.inference._gibbs_moves import add_pair
from bsi_sklearn.inference._row_counts import flip_masks, flip_sums, mask_sums
from bsi_sklearn.inference.mcmc import deduplicate_demos


@njit
def _both_ways(viol, masks, demos, clauses, incs):
    # For every (clause, bit) pair: flip_sums row by row and mask_sums from the bitsets; the
    # clause then flipped into viol (and the masks rebuilt), as a chain's flips do.
    out = np.empty((clauses.shape[0], 2, 4))
    for i in range(clauses.shape[0]):
        c, inc = clauses[i], incs[i]
        out[i, 0] = flip_sums(viol, demos.truth_t, c, inc, demos.w_pos, demos.w_neg)
        out[i, 1] = mask_sums(masks, c, inc, demos)
        add_pair(viol, demos.truth_t, c, np.int64(-1 if inc else 1))
        flip_masks(viol, masks)
    return out


@pytest.mark.parametrize("n_rows, repeats", [(1, 1), (63, 1), (64, 3), (200, 5), (700, 1)])
def test_mask_sums_equal_flip_sums_bit_for_bit(n_rows, repeats):
    # Rows across word boundaries, repeated rows (weights above 1: several bit-planes), and
    # violation counts of 0, 1 and more, the clause in and out.
    rng = np.random.default_rng(n_rows)
    n_clauses = 12
    truth = (rng.random((n_rows * repeats, n_clauses)) < 0.8).astype(np.uint8)
    truth[n_rows:] = truth[rng.integers(0, n_rows, len(truth) - n_rows)]
    y = (rng.random(len(truth)) < 0.6).astype(np.int64)
    demos = deduplicate_demos(truth, y)
    inc = np.zeros(n_clauses, dtype=np.int64)
    inc[rng.random(n_clauses) < 0.5] = 1
    viol = ((demos.truth_t == 0) * inc[:, None]).sum(axis=0).astype(np.int32)
    masks = np.zeros((2, demos.bits.shape[1]), dtype=np.uint64)
    flip_masks(viol, masks)
    clauses = rng.integers(0, n_clauses, 60)
    incs = np.empty(60, dtype=np.int64)
    for i, c in enumerate(clauses):  # each clause's bit as the flips before it leave it
        incs[i] = inc[c]
        inc[c] = 1 - inc[c]
    got = _both_ways(viol, masks, demos, clauses, incs)
    np.testing.assert_array_equal(got[:, 0], got[:, 1])  # equal, not close
    assert np.unique(got[:, 0, 0]).size > 1
