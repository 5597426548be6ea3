"""Validation, padding and in-length reversal of variable-length numeric sequences."""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

__all__ = [
    "Sequences",
    "check_sequences",
    "check_consistent_sequences",
    "check_phases",
    "pad_sequences",
    "reverse_index",
    "length_mask",
]


@dataclass(frozen=True)
class Sequences:
    """Validated sequences, stacked one after the other.

    Attributes
    ----------
    data : ndarray of shape (sum(T_i), n_features), dtype float64
        All time steps of all sequences.
    offsets : ndarray of shape (n_sequences + 1,), dtype int64
        Sequence ``i`` is ``data[offsets[i]:offsets[i + 1]]``.
    feature_names : ndarray of str or None
        Feature names when the input carried string column names.
    """

    data: np.ndarray
    offsets: np.ndarray
    feature_names: np.ndarray | None

    @property
    def n_sequences(self):
        """Number of sequences."""
        return len(self.offsets) - 1

    @property
    def n_features(self):
        """Number of features per time step."""
        return self.data.shape[1]

    @property
    def lengths(self):
        """Length of every sequence."""
        return np.diff(self.offsets)

    def sequence(self, i):
        """Sequence ``i`` as an array ``(T_i, n_features)``."""
        return self.data[self.offsets[i] : self.offsets[i + 1]]

    def subset(self, indices):
        """Return the sequences at ``indices``, in that order."""
        indices = np.asarray(indices, dtype=np.int64)
        lengths = self.lengths[indices]
        offsets = np.zeros(len(indices) + 1, dtype=np.int64)
        np.cumsum(lengths, out=offsets[1:])
        if len(indices):
            data = np.concatenate([self.sequence(i) for i in indices], axis=0)
        else:
            data = np.empty((0, self.n_features))
        return Sequences(data, offsets, self.feature_names)


def _is_frame(obj):
    return hasattr(obj, "columns") and hasattr(obj, "to_numpy") and hasattr(obj, "iloc")


def _frame_names(frame, where):
    cols = list(frame.columns)
    str_cols = [isinstance(c, str) for c in cols]
    if cols and all(str_cols):
        if len(set(cols)) != len(cols):
            raise ValueError(f"{where} has duplicate column names")
        return np.asarray(cols, dtype=object)
    if any(str_cols):
        raise ValueError(
            f"{where} mixes string and non-string column names; use strings for all columns"
        )
    return None


def _to_float(arr, where):
    """Turn one sequence's values into finite float64, or raise naming ``where``."""
    if arr.dtype.kind == "c":
        raise ValueError(f"Complex data not supported: {where} has complex values")
    if arr.dtype.kind not in "biuf":
        try:
            arr = arr.astype(np.float64)
        except ValueError as exc:
            raise ValueError(f"{where} has non-numeric values: {exc}") from None
        except TypeError as exc:
            raise TypeError(f"{where} has non-numeric values: {exc}") from None
    arr = np.asarray(arr, dtype=np.float64)
    bad = ~np.isfinite(arr)
    if bad.any():
        t, f = map(int, np.argwhere(bad)[0])
        raise ValueError(f"{where} has a NaN or infinite value at step {t}, feature {f}")
    return arr


def check_sequences(X, *, estimator_name="estimator"):
    """Validate sequences of numeric (or boolean) feature vectors.

    Parameters
    ----------
    X : list of array-like or DataFrame, 3-D array or 2-D array
        The formats of :func:`bsi_sklearn._validation.check_traces` (DESIGN section 1), with
        numeric values allowed: a list (or tuple) of ``(T_i, n_features)`` arrays, a list of
        DataFrames (rows are time steps; column names must agree), a 3-D array
        ``(n_sequences, T, n_features)``, or a 2-D array ``(n_sequences, n_features)`` (or a
        single DataFrame) whose rows are sequences of length one.
    estimator_name : str, default="estimator"
        Used in messages.

    Returns
    -------
    sequences : Sequences

    Raises
    ------
    ValueError
        For NaN or infinite values, non-numeric values, zero-length sequences, zero sequences,
        zero features, ragged input or feature counts / names that differ between sequences;
        the message names the offending sequence.
    TypeError
        For sparse input or values that cannot be converted to numbers at all.

    Examples
    --------
    >>> import numpy as np
    >>> from baselines._sequences import check_sequences
    >>> seqs = check_sequences([np.zeros((3, 2)), np.ones((5, 2))])
    >>> seqs.n_sequences, seqs.n_features, seqs.lengths.tolist()
    (2, 2, [3, 5])
    """
    if X is None:
        raise ValueError(f"{estimator_name} expects sequences, got None")
    if sp.issparse(X):
        raise TypeError(
            f"{estimator_name} does not support sparse input; pass a list of dense arrays"
        )
    if _is_frame(X):
        names = _frame_names(X, "the DataFrame")
        return _stack_rows(_to_float(X.to_numpy(), "the DataFrame"), names, estimator_name)
    if isinstance(X, (list, tuple)):
        if len(X) == 0:
            raise ValueError(f"{estimator_name} needs at least one sequence, got 0")
        if not any(_is_frame(item) or np.ndim(item) >= 2 for item in X):
            # a nested list of rows (or of scalars): read it as one array, like the 2-D layout
            try:
                arr = np.asarray(X)
            except ValueError as exc:
                raise ValueError(f"X is a ragged list of rows: {exc}") from None
            if arr.ndim == 2:
                return _stack_rows(_to_float(arr, "X"), None, estimator_name)
            raise _not_sequences(arr.ndim)
        return _stack_list(X)
    if isinstance(X, np.ndarray) or hasattr(X, "__array__"):
        arr = np.asarray(X)
    else:
        raise ValueError(
            "sequences must be a list of 2-D arrays or DataFrames, or a 2-D / 3-D array; "
            f"got {type(X).__name__}"
        )
    if arr.dtype == object and arr.ndim == 1:
        if arr.shape[0] == 0:
            raise ValueError(f"{estimator_name} needs at least one sequence, got 0")
        return _stack_list(list(arr))
    if arr.ndim == 3:
        if arr.shape[0] == 0:
            raise ValueError(f"{estimator_name} needs at least one sequence, got 0")
        return _stack_list(list(arr))
    if arr.ndim == 2:
        return _stack_rows(_to_float(arr, "X"), None, estimator_name)
    raise _not_sequences(arr.ndim)


def _not_sequences(ndim):
    return ValueError(
        "sequences must be a list of 2-D arrays, a 3-D array (n_sequences, T, n_features) or a "
        f"2-D array (n_sequences, n_features); got an array with {ndim} dimension(s). Reshape "
        "your data with array.reshape(-1, 1) if it has a single feature or array.reshape(1, -1) "
        "if it is a single sample"
    )


def _stack_rows(rows, names, estimator_name):
    if rows.shape[0] == 0:
        raise ValueError(
            f"Found array with 0 sample(s) (shape={rows.shape}) while a minimum of 1 is "
            f"required by {estimator_name}"
        )
    if rows.shape[1] == 0:
        raise ValueError(
            f"Found array with 0 feature(s) (shape={rows.shape}) while a minimum of 1 is "
            f"required by {estimator_name}"
        )
    offsets = np.arange(rows.shape[0] + 1, dtype=np.int64)
    return Sequences(np.ascontiguousarray(rows), offsets, names)


def _stack_list(items):
    arrays, names, n_features = [], None, None
    for i, item in enumerate(items):
        where = f"sequence {i}"
        if _is_frame(item):
            item_names = _frame_names(item, where)
            if i == 0:
                names = item_names
            elif (names is None) != (item_names is None) or (
                names is not None and list(names) != list(item_names)
            ):
                raise ValueError(
                    f"{where} has columns {list(item.columns)}, but sequence 0 has "
                    f"{list(names) if names is not None else 'no string names'}"
                )
            arr = item.to_numpy()
        else:
            if i > 0 and names is not None:
                raise ValueError(f"{where} is not a DataFrame, but sequence 0 is")
            try:
                arr = np.asarray(item)
            except ValueError as exc:
                raise ValueError(f"{where} is ragged: {exc}") from None
        if arr.dtype == object and arr.ndim == 1:
            raise ValueError(f"{where} is ragged or not a 2-D array (T, n_features)")
        if arr.ndim != 2:
            raise ValueError(
                f"{where} must be a 2-D array (T, n_features), got {arr.ndim} dimension(s) "
                f"with shape {arr.shape}"
            )
        if arr.shape[0] == 0:
            raise ValueError(f"{where} has zero length; every sequence needs at least one step")
        if arr.shape[1] == 0:
            raise ValueError(f"{where} has 0 features; at least one is required")
        if n_features is None:
            n_features = arr.shape[1]
        elif arr.shape[1] != n_features:
            raise ValueError(
                f"{where} has {arr.shape[1]} features, but sequence 0 has {n_features}"
            )
        arrays.append(_to_float(arr, where))
    lengths = np.array([a.shape[0] for a in arrays], dtype=np.int64)
    offsets = np.zeros(len(arrays) + 1, dtype=np.int64)
    np.cumsum(lengths, out=offsets[1:])
    return Sequences(np.ascontiguousarray(np.concatenate(arrays, axis=0)), offsets, names)


def check_consistent_sequences(sequences, n_features_in, feature_names_in, estimator_name):
    """Check that sequences given after fit have the features seen in fit.

    The messages are scikit-learn's, so its estimator checks recognise them.
    """
    if sequences.n_features != n_features_in:
        raise ValueError(
            f"X has {sequences.n_features} features, but {estimator_name} is expecting "
            f"{n_features_in} features as input."
        )
    fitted, given = feature_names_in, sequences.feature_names
    if fitted is not None and given is not None:
        if list(fitted) != list(given):
            raise ValueError(
                "The feature names should match those that were passed during fit.\n"
                f"Fitted with: {list(fitted)}\nGot: {list(given)}"
            )
    elif fitted is not None:
        warnings.warn(
            f"X does not have valid feature names, but {estimator_name} was fitted with "
            "feature names",
            UserWarning,
            stacklevel=3,
        )
    elif given is not None:
        warnings.warn(
            f"X has feature names, but {estimator_name} was fitted without feature names",
            UserWarning,
            stacklevel=3,
        )


def check_phases(phases, lengths, n_phases):
    """Validate per-time-step phase labels against the sequence lengths.

    Parameters
    ----------
    phases : list of array-like of int
        One 1-D array per sequence, as long as the sequence, values in ``[0, n_phases)``.
    lengths : ndarray of int
        Length of every sequence.
    n_phases : int
        Number of phase classes.

    Returns
    -------
    phases : ndarray of shape (sum(lengths),), dtype int64
        All labels, one sequence after the other (aligned with ``Sequences.data``).

    Examples
    --------
    >>> import numpy as np
    >>> from baselines._sequences import check_phases
    >>> check_phases([[0, 1, 1], [0, 2]], np.array([3, 2]), 3).tolist()
    [0, 1, 1, 0, 2]
    """
    if isinstance(phases, np.ndarray) and phases.dtype != object and phases.ndim == 2:
        phases = list(phases)
    if not isinstance(phases, (list, tuple, np.ndarray)) and not _is_frame(phases):
        raise ValueError(
            "phases must be a list of 1-D integer arrays, one per sequence; "
            f"got {type(phases).__name__}"
        )
    if _is_frame(phases):
        raise ValueError("phases must be a list of 1-D integer arrays, not a DataFrame")
    if len(phases) != len(lengths):
        raise ValueError(
            f"phases has {len(phases)} entries but there are {len(lengths)} sequences"
        )
    out = []
    for i, (p, length) in enumerate(zip(phases, lengths, strict=True)):
        arr = np.asarray(p.to_numpy() if hasattr(p, "to_numpy") else p)
        if arr.ndim == 2 and arr.shape[1] == 1:
            arr = arr[:, 0]
        if arr.ndim != 1:
            raise ValueError(
                f"phases of sequence {i} must be 1-D (one label per time step), got shape "
                f"{arr.shape}"
            )
        if arr.shape[0] != length:
            raise ValueError(
                f"phases of sequence {i} has {arr.shape[0]} labels but the sequence has "
                f"{length} steps"
            )
        if arr.dtype.kind == "f":
            if not np.all(np.isfinite(arr)) or np.any(arr != np.round(arr)):
                raise ValueError(f"phases of sequence {i} must be integers")
        elif arr.dtype.kind not in "biu":
            raise ValueError(
                f"phases of sequence {i} must be integers in [0, {n_phases}), got dtype "
                f"{arr.dtype}"
            )
        arr = arr.astype(np.int64)
        bad = (arr < 0) | (arr >= n_phases)
        if bad.any():
            t = int(np.argmax(bad))
            raise ValueError(
                f"phases of sequence {i} has label {arr[t]} at step {t}; labels must be in "
                f"[0, n_phases={n_phases})"
            )
        out.append(arr)
    return np.concatenate(out) if out else np.empty(0, dtype=np.int64)


def pad_sequences(data, offsets, indices, *, fill=0.0):
    """Stack the sequences at ``indices`` into a zero-padded array.

    Parameters
    ----------
    data : ndarray of shape (sum(T_i), ...)
        Stacked per-step values (features or labels).
    offsets : ndarray of shape (n_sequences + 1,)
        Sequence boundaries in ``data``.
    indices : array-like of int
        Which sequences, in which order.
    fill : scalar, default=0.0
        Value of the padded steps.

    Returns
    -------
    padded : ndarray of shape (len(indices), max T_i, ...)
        Sequence ``k`` occupies ``padded[k, :lengths[k]]``; later steps hold ``fill``.
    lengths : ndarray of shape (len(indices),), dtype int64

    Examples
    --------
    >>> import numpy as np
    >>> from baselines._sequences import pad_sequences
    >>> data = np.arange(5.0)[:, None]
    >>> padded, lengths = pad_sequences(data, np.array([0, 2, 5]), [1, 0])
    >>> padded[..., 0].tolist(), lengths.tolist()
    ([[2.0, 3.0, 4.0], [0.0, 1.0, 0.0]], [3, 2])
    """
    indices = np.asarray(indices, dtype=np.int64)
    starts, ends = offsets[indices], offsets[indices + 1]
    lengths = ends - starts
    t_max = int(lengths.max()) if len(lengths) else 0
    padded = np.full((len(indices), t_max) + data.shape[1:], fill, dtype=data.dtype)
    for k, (s, e) in enumerate(zip(starts, ends, strict=True)):
        padded[k, : e - s] = data[s:e]
    return padded, lengths


def reverse_index(lengths, t_max):
    """Time indices that reverse every sequence inside its own length.

    ``index[k, t] = lengths[k] - 1 - t`` for ``t < lengths[k]`` and ``t`` afterwards, so
    gathering a padded batch along time with it reverses each sequence while its padding stays
    at the end. It is its own inverse. Running a forward recurrence over the reversed batch is
    the backward direction of a bidirectional network, unaffected by the padding.

    Parameters
    ----------
    lengths : ndarray of int
        Length of every sequence of the batch.
    t_max : int
        Padded length.

    Returns
    -------
    index : ndarray of shape (len(lengths), t_max), dtype int64

    Examples
    --------
    >>> import numpy as np
    >>> from baselines._sequences import reverse_index
    >>> reverse_index(np.array([3, 1]), 4).tolist()
    [[2, 1, 0, 3], [0, 1, 2, 3]]
    """
    lengths = np.asarray(lengths, dtype=np.int64)
    t = np.arange(t_max, dtype=np.int64)[None, :]
    return np.where(t < lengths[:, None], lengths[:, None] - 1 - t, t)


def length_mask(lengths, t_max):
    """Boolean mask ``(len(lengths), t_max)``, true on the valid (non-padded) steps.

    Examples
    --------
    >>> import numpy as np
    >>> from baselines._sequences import length_mask
    >>> length_mask(np.array([2, 3]), 3).astype(int).tolist()
    [[1, 1, 0], [1, 1, 1]]
    """
    lengths = np.asarray(lengths, dtype=np.int64)
    return np.arange(t_max, dtype=np.int64)[None, :] < lengths[:, None]

