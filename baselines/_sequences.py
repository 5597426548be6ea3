"""Validation, padding and in-length reversal of variable-length numeric sequences."""

from __future__ import annotations

import numpy as np

from bsi_sklearn.data.traces import (
    Traces,
    Wording,
    check_consistent_traces,
    check_traces,
    is_frame,
)

__all__ = [
    "Sequences",
    "check_sequences",
    "check_consistent_sequences",
    "check_phases",
    "pad_sequences",
    "reverse_index",
    "length_mask",
]


class Sequences(Traces):
    """Validated sequences, stacked one after the other.

    A :class:`bsi_sklearn.data.traces.Traces` of numeric values, read as sequences of feature
    vectors.

    Attributes
    ----------
    data : ndarray of shape (sum(T_i), n_features), dtype float64
        All time steps of all sequences.
    offsets : ndarray of shape (n_sequences + 1,), dtype int64
        Sequence ``i`` is ``data[offsets[i]:offsets[i + 1]]``.
    feature_names : ndarray of str or None
        Feature names when the input carried string column names.

    ``lengths`` is the ``Traces``' own; ``n_sequences`` and ``n_features`` are its
    ``n_demos`` and ``n_props`` under the names of this package.
    """

    @property
    def n_sequences(self):
        """Number of sequences."""
        return self.n_demos

    @property
    def n_features(self):
        """Number of features per time step."""
        return self.n_props

    def sequence(self, i):
        """Sequence ``i`` as an array ``(T_i, n_features)`` (its values, not booleans)."""
        return self.data[self.offsets[i] : self.offsets[i + 1]]


_SEQUENCE_WORDS = Wording(item="sequence", unit="feature")


def check_sequences(X, *, estimator_name="estimator"):
    """Validate sequences of numeric (or boolean) feature vectors.

    Parameters
    ----------
    X : list of array-like or DataFrame, 3-D array or 2-D array
        The formats of :func:`bsi_sklearn.data.traces.check_traces`, with numeric values
        allowed: a list (or tuple) of ``(T_i, n_features)`` arrays, a list of DataFrames
        (rows are time steps; column names must agree), a 3-D array
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
    t = check_traces(X, estimator_name=estimator_name, numeric=True, words=_SEQUENCE_WORDS,
                     frame_as_rows=True)
    return Sequences(t.data, t.offsets, t.feature_names)


def check_consistent_sequences(sequences, n_features_in, feature_names_in, estimator_name):
    """Check that sequences given after fit have the features seen in fit.

    The messages are scikit-learn's, so its estimator checks recognise them.
    """
    check_consistent_traces(sequences, n_features_in, feature_names_in, estimator_name,
                            _SEQUENCE_WORDS)


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
    if not isinstance(phases, (list, tuple, np.ndarray)) and not is_frame(phases):
        raise ValueError(
            "phases must be a list of 1-D integer arrays, one per sequence; "
            f"got {type(phases).__name__}"
        )
    if is_frame(phases):
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

