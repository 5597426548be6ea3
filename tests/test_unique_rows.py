"""unique_rows against np.unique(axis=0): the same first indices and inverse, any small ints."""

import numpy as np
import pytest

from bsi_sklearn._unique_rows import unique_rows


@pytest.mark.parametrize("dtype", [np.int8, np.int16, np.int64, np.uint8, bool])
@pytest.mark.parametrize("seed", range(20))
def test_unique_rows_is_np_unique(dtype, seed):
    rng = np.random.default_rng(seed)
    n, width = int(rng.integers(1, 150)), int(rng.integers(1, 70))
    low = 0 if dtype in (np.uint8, bool) else int(rng.integers(-8, 4))
    high = low + (2 if dtype is bool else int(rng.integers(1, 40)))
    a = rng.integers(low, high, size=(n, width)).astype(dtype)
    a = np.concatenate([a, a[rng.integers(0, n, size=n)]])  # repeats, in any order
    _, first, inverse = np.unique(a, axis=0, return_index=True, return_inverse=True)
    got_first, got_inverse = unique_rows(a)
    np.testing.assert_array_equal(got_first, first)
    np.testing.assert_array_equal(got_inverse, inverse.ravel())


def test_unique_rows_wide_values_and_edges():
    # values too wide to pack fall back to np.unique; empty and zero-width inputs too
    a = np.array([[2**62, -(2**62)], [0, 1], [2**62, -(2**62)]], dtype=np.int64)
    first, inverse = unique_rows(a)
    assert first.tolist() == [1, 0] and inverse.tolist() == [1, 0, 1]
    first, inverse = unique_rows(np.empty((0, 3), dtype=np.int16))
    assert len(first) == 0 and len(inverse) == 0
    first, inverse = unique_rows(np.empty((4, 0), dtype=np.int16))
    assert first.tolist() == [0] and inverse.tolist() == [0, 0, 0, 0]
