"""Distinct rows of a small-integer array: sorted as ``np.unique(axis=0)`` does, or keyed.

``np.unique(a, axis=0)`` sorts the rows as structured scalars, compared field by field: on
the sampler's visited states (tens of columns, 1e5 rows) that sort took most of a 500-sweep
fit's post-processing. Here each row is packed into a few 63-bit words (the values shifted to
be non-negative, most significant column first), the words are sorted with ``np.lexsort``
(stable), and neighbours in that order are compared. The order is the same numeric
lexicographic order and every first index the same first occurrence, so the results are
identical to ``np.unique``'s. :func:`row_keys` gives each row's bytes, the key a dictionary or
set tells rows apart by.
"""

import numpy as np

__all__ = ["unique_rows", "row_keys"]


def unique_rows(a):
    """``np.unique(a, axis=0, return_index=True, return_inverse=True)`` less the rows.

    Parameters
    ----------
    a : ndarray of shape (n_rows, n_cols), integer or boolean

    Returns
    -------
    first : ndarray of shape (n_unique,), int64
        The index of the first occurrence of every distinct row, the rows in ascending
        lexicographic (numeric) order.
    inverse : ndarray of shape (n_rows,), int64
        The index of every row among the distinct rows.

    Examples
    --------
    >>> import numpy as np
    >>> first, inverse = unique_rows(np.array([[1, 0], [0, 2], [1, 0]]))
    >>> first.tolist(), inverse.tolist()
    ([1, 0], [1, 0, 1])
    """
    a = np.asarray(a)
    n, width = a.shape
    if n == 0 or width == 0 or a.dtype.kind not in "biu":
        _, first, inverse = np.unique(a, axis=0, return_index=True, return_inverse=True)
        return first.astype(np.int64), inverse.ravel().astype(np.int64)
    low, high = int(a.min()), int(a.max())
    bits = max((high - low).bit_length(), 1)
    if bits > 62:  # a column would not fit a word: np.unique's own sort
        _, first, inverse = np.unique(a, axis=0, return_index=True, return_inverse=True)
        return first.astype(np.int64), inverse.ravel().astype(np.int64)
    per = 63 // bits
    words = []
    for start in range(0, width, per):  # a block of columns at a time: no int64 copy of `a`
        block = a[:, start:start + per].astype(np.int64) - low
        weights = np.left_shift(np.int64(1), bits * np.arange(block.shape[1] - 1, -1, -1,
                                                               dtype=np.int64))
        words.append(block @ weights)
    # np.lexsort sorts by its last key first: the first word is the most significant.
    order = np.lexsort(words[::-1]) if len(words) > 1 else np.argsort(words[0],
                                                                       kind="stable")
    packed = np.stack(words, axis=1)[order]
    new = np.empty(n, dtype=bool)
    new[0] = True
    new[1:] = np.any(packed[1:] != packed[:-1], axis=1)
    inverse = np.empty(n, dtype=np.int64)
    inverse[order] = np.cumsum(new) - 1
    return order[new].astype(np.int64), inverse


def row_keys(rows):
    """Every row's bytes as int16, in one C-level pass: the keys rows are told apart by.

    Examples
    --------
    >>> import numpy as np
    >>> keys = row_keys(np.array([[1, 0], [1, 0], [0, 2]]))
    >>> keys[0] == keys[1] != keys[2], keys[0] == np.array([1, 0], dtype=np.int16).tobytes()
    (True, True)
    """
    rows = np.ascontiguousarray(rows, dtype=np.int16)
    if rows.shape[1] == 0:
        return [b""] * len(rows)
    return rows.view(np.dtype((np.void, 2 * rows.shape[1]))).ravel().tolist()
