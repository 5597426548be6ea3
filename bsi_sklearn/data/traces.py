"""Demonstrations (traces) and labels: the ``Traces`` data model and the checks that build it."""

from __future__ import annotations

import numbers
import warnings
from dataclasses import dataclass

import numpy as np

from bsi_sklearn.data._labels import check_labels
from bsi_sklearn.data.long_format import traces_from_frame
from bsi_sklearn.data.values import (
    NonNumericTraceError,
    Place,
    frame_names,
    names_difference,
    ragged_error,
    ragged_rows_error,
    to_bool,
    to_float,
)

__all__ = [
    "Traces",
    "Wording",
    "NonNumericTraceError",
    "is_frame",
    "check_traces",
    "check_consistent_traces",
    "check_labels",
]


@dataclass(frozen=True)
class Traces:
    """Demonstrations stacked for the kernels.

    Attributes
    ----------
    data : ndarray of shape (sum(T_i), n_props), dtype uint8
        All time steps of all demonstrations, one after the other.
    offsets : ndarray of shape (n_demos + 1,), dtype int64
        Demonstration ``i`` is ``data[offsets[i]:offsets[i + 1]]``.
    feature_names : ndarray of str or None
        Proposition names when the input carried string column names.

    See Also
    --------
    check_traces : Builds a ``Traces`` from any accepted input format.

    Examples
    --------
    >>> import numpy as np
    >>> traces = check_traces([np.array([[1, 0], [1, 1]]), np.array([[0, 1]])])
    >>> traces.n_demos, traces.n_props, traces.lengths.tolist()
    (2, 2, [2, 1])
    >>> traces.trace(1)
    array([[False,  True]])
    """

    data: np.ndarray
    offsets: np.ndarray
    feature_names: np.ndarray | None

    @property
    def n_demos(self):
        """Number of demonstrations."""
        return len(self.offsets) - 1

    @property
    def n_props(self):
        """Number of propositions."""
        return self.data.shape[1]

    @property
    def lengths(self):
        """Length of every demonstration."""
        return np.diff(self.offsets)

    def trace(self, i):
        """Demonstration ``i`` as a boolean array ``(T_i, n_props)``."""
        return self.data[self.offsets[i] : self.offsets[i + 1]].astype(bool)


def is_frame(obj):
    """Whether ``obj`` is a pandas DataFrame (duck-typed, so pandas need not be imported).

    Parameters
    ----------
    obj : object
        Anything.

    Returns
    -------
    answer : bool
        True when ``obj`` has ``columns``, ``to_numpy`` and ``iloc``.

    Examples
    --------
    >>> import numpy as np, pandas as pd
    >>> is_frame(pd.DataFrame({"a": [1]})), is_frame(np.ones((1, 1)))
    (True, False)
    """
    return hasattr(obj, "columns") and hasattr(obj, "to_numpy") and hasattr(obj, "iloc")


@dataclass(frozen=True)
class Wording:
    """What the items and their columns are called in validation messages.

    Attributes
    ----------
    item : str, default="demonstration"
        One element of the collection (``"sequence"`` for the numeric sequences of
        ``baselines``).
    unit : str, default="proposition"
        One column of an item (``"feature"`` for numeric sequences).

    Examples
    --------
    >>> import numpy as np
    >>> check_traces([np.zeros((0, 2))], words=Wording(item="sequence", unit="feature"))
    Traceback (most recent call last):
    ...
    ValueError: sequence 0 has zero length; every sequence needs at least one step
    """

    item: str = "demonstration"
    unit: str = "proposition"


_TRACE_WORDING = Wording()


def check_traces(X, *, binarize=None, estimator_name="estimator", numeric=False,
                 words=_TRACE_WORDING, frame_as_rows=False):
    """Validate demonstrations and stack them for the kernels.

    Parameters
    ----------
    X : list of 2-D array-like or DataFrame, 3-D array, 2-D array or long-format DataFrame
        The accepted formats, and nothing else:

        - a list (or tuple) of ``(T_i, n_props)`` arrays or DataFrames, one per
          demonstration (rows are time steps; lengths may differ);
        - a 3-D array ``(n_demos, T, n_props)``;
        - a 2-D array ``(n_demos, n_props)`` or a list of lists of numbers (scikit-learn's
          format): every row is a demonstration of length one;
        - a long-format DataFrame with a ``demo_id`` column (and optionally ``t``), one row
          per time step (see :func:`bsi_sklearn.io.traces_from_frame`).

        A single DataFrame without ``demo_id`` is rejected (pass ``[df]`` for one
        demonstration), and so is a list of 1-D arrays (reshape each with
        ``x.reshape(-1, 1)`` for one proposition over time).
    binarize : float or None, default=None
        When set, values ``> binarize`` become true; otherwise values must be 0/1 or boolean.
    estimator_name : str
        Used in messages.
    numeric : bool, default=False
        Keep finite real values as float64 instead of requiring booleans (the sequence models
        of ``baselines`` share this validation).
    words : Wording, default=Wording()
        Names of the items and columns in messages.
    frame_as_rows : bool, default=False
        Read a single DataFrame without ``demo_id`` as the 2-D format (rows are items of
        length one) instead of rejecting it (the numeric sequences of ``baselines``).

    Returns
    -------
    traces : Traces

    Raises
    ------
    ValueError
        Naming the demonstration, the step and the proposition (by column name when there is
        one) of the first bad value, or saying which format was expected.

    Examples
    --------
    >>> import numpy as np, pandas as pd
    >>> df = pd.DataFrame({"safe": [1, 1, 0], "done": [0, 1, 1]})
    >>> check_traces([df]).lengths.tolist()
    [3]
    >>> check_traces(df)
    Traceback (most recent call last):
    ...
    ValueError: estimator got a single DataFrame without a 'demo_id' column...
    >>> check_traces([np.array([0, 1, 1])])
    Traceback (most recent call last):
    ...
    ValueError: demonstration 0 is a 1-D array of shape (3,)...
    """
    if binarize is not None and (
        not isinstance(binarize, numbers.Real) or isinstance(binarize, bool)
        or not np.isfinite(binarize)
    ):
        raise ValueError(f"binarize must be None or a finite number, got {binarize!r}")
    convert = to_float if numeric else to_bool
    items = words.item + "s"
    if X is None:
        raise ValueError(f"{estimator_name} expects {items}, got None")
    if hasattr(X, "tocsr") or hasattr(X, "to_dense") and not is_frame(X):
        raise TypeError(
            f"{estimator_name} does not support sparse input; pass dense arrays "
            "(e.g. X.toarray())"
        )
    names = None
    if is_frame(X):
        if "demo_id" in X.columns:
            return _long_frame(X, binarize, estimator_name, numeric, words)
        if not frame_as_rows:
            raise ValueError(
                f"{estimator_name} got a single DataFrame without a 'demo_id' column "
                f"({X.shape[0]} rows, columns {list(X.columns)[:8]}). Pass [df] if it is one "
                f"{words.item} (rows are time steps), a list of DataFrames for several, or a "
                "long-format frame with a 'demo_id' column (optional 't') whose rows are the "
                f"steps of all {items}"
            )
        names = frame_names(X, "the DataFrame")
        X = X.to_numpy()
    if isinstance(X, (list, tuple)):
        if len(X) == 0:
            raise ValueError(f"{estimator_name} needs at least one {words.item}, got 0")
        first = X[0]
        if isinstance(first, (list, tuple)) and all(np.ndim(v) == 0 for v in first):
            # Nested lists of scalars: scikit-learn's 2-D format (each row a trace of length one).
            try:
                arr = np.asarray(X)
            except ValueError:
                arr = None
            if arr is not None and arr.ndim == 2:
                return check_traces(arr, binarize=binarize, estimator_name=estimator_name,
                                    numeric=numeric, words=words)
            raise ragged_rows_error(X, estimator_name, words.item, words.unit)
        return _stack_list(X, convert, binarize, words)
    if hasattr(X, "__array__") or isinstance(X, np.ndarray):
        arr = np.asarray(X)
    else:
        raise ValueError(
            f"{items} must be a list of 2-D arrays or DataFrames, or a 2-D / 3-D array; "
            f"got {type(X).__name__}"
        )
    if arr.dtype == object and arr.ndim != 2:
        return _stack_list(list(arr), convert, binarize, words)
    if arr.ndim == 3:
        if arr.shape[0] == 0:
            raise ValueError(f"{estimator_name} needs at least one {words.item}, got 0")
        return _stack_list(list(arr), convert, binarize, words)
    if arr.ndim == 2:
        if arr.shape[0] == 0:
            raise ValueError(
                f"{estimator_name} needs at least one {words.item}: found array with 0 "
                f"sample(s) (shape={arr.shape}) while a minimum of 1 is required."
            )
        if arr.shape[1] == 0:
            raise ValueError(
                f"{items} have no {words.unit}s: found array with 0 feature(s) "
                f"(shape={arr.shape}) while a minimum of 1 is required."
            )
        rows = convert(arr, Place(words.item, words.unit, None, names), binarize)
        return _stack_rows(rows, names, words)
    hint = (" Reshape your data: X.reshape(1, -1) for one trace of length one, or wrap a "
            "(T, n_props) trace in a list." if arr.ndim == 1 else "")
    raise ValueError(
        f"{items} must be a list of 2-D arrays, a 3-D array (n_{items}, T, n_{words.unit}s) "
        f"or a 2-D array (n_{items}, n_{words.unit}s); got an array with {arr.ndim} "
        f"dimension(s).{hint}"
    )


def _long_frame(frame, binarize, estimator_name, numeric, words):
    """A long-format frame (``demo_id``, optional ``t``) split into demonstrations."""
    if "label" in frame.columns:
        raise ValueError(
            f"{estimator_name} got a long-format frame with a 'label' column; split it first: "
            "X, y = bsi_sklearn.io.traces_from_frame(df), then pass X (and y)"
        )
    if "t" not in frame.columns:
        frame = frame.assign(t=frame.groupby("demo_id", sort=False).cumcount())
    parts, _ = traces_from_frame(frame, label_col=None)
    return check_traces(parts, binarize=binarize, estimator_name=estimator_name,
                        numeric=numeric, words=words)


def _stack_rows(rows, names, words):
    offsets = np.arange(rows.shape[0] + 1, dtype=np.int64)
    return Traces(np.ascontiguousarray(rows), offsets, names)


def _stack_list(items, convert, binarize, words):
    arrays, names, n_props = [], None, None
    unit = words.unit
    for i, item in enumerate(items):
        where = f"{words.item} {i}"
        if is_frame(item):
            item_names = frame_names(item, where)
            if i == 0:
                names = item_names
            elif (names is None) != (item_names is None):
                raise ValueError(
                    f"{where} has columns {list(item.columns)}, but {words.item} 0 has "
                    f"{list(names) if names is not None else 'no string names'}"
                )
            elif list(names) != list(item_names):
                # e.g. demonstrations of files with different headers: name the column
                expected, got = [str(n) for n in names], [str(n) for n in item_names]
                raise ValueError(
                    f"{where} has columns {got}, but {words.item} 0 has {expected}: "
                    f"{names_difference(expected, got, unit, where, f'{words.item} 0')}"
                )
            arr = item.to_numpy()
        else:
            if i > 0 and names is not None:
                raise ValueError(f"{where} is not a DataFrame, but {words.item} 0 is")
            try:
                arr = np.asarray(item)
            except ValueError:
                raise ragged_error(item, where, unit) from None
        if arr.dtype == object and arr.ndim == 1 and len(arr) and np.ndim(arr[0]) > 0:
            raise ragged_error(item, where, unit)
        if arr.ndim == 1:
            raise ValueError(
                f"{where} is a 1-D array of shape {arr.shape}; a {words.item} is a 2-D array "
                f"(T, n_{unit}s) whose rows are time steps. For one {unit} over time use "
                f"x.reshape(-1, 1); for {words.item}s of length one pass a 2-D array "
                f"(n_{words.item}s, n_{unit}s)"
            )
        if arr.ndim != 2:
            raise ValueError(
                f"{where} must be a 2-D array (T, n_{unit}s), got {arr.ndim} dimension(s) "
                f"with shape {arr.shape}"
            )
        if arr.shape[0] == 0:
            raise ValueError(f"{where} has zero length; every {words.item} needs at least one "
                             "step")
        if arr.shape[1] == 0:
            raise ValueError(f"{where} has 0 {unit}s; at least one is required")
        if n_props is None:
            n_props = arr.shape[1]
        elif arr.shape[1] != n_props:
            raise ValueError(
                f"{where} has {arr.shape[1]} {unit}s, but {words.item} 0 has {n_props}"
            )
        place = Place(words.item, unit, i, names)
        arrays.append(convert(arr, place, binarize))
    lengths = np.array([a.shape[0] for a in arrays], dtype=np.int64)
    offsets = np.zeros(len(arrays) + 1, dtype=np.int64)
    np.cumsum(lengths, out=offsets[1:])
    return Traces(np.ascontiguousarray(np.concatenate(arrays, axis=0)), offsets, names)


def check_consistent_traces(traces, n_features_in, feature_names_in, estimator_name,
                            words=_TRACE_WORDING):
    """Check that traces given after fit have the propositions seen in fit.

    Parameters
    ----------
    traces : Traces
        The traces given after fit (from :func:`check_traces`).
    n_features_in : int
        Number of propositions seen in fit.
    feature_names_in : ndarray of str or None
        Proposition names seen in fit.
    estimator_name : str
        Used in messages.
    words : Wording, default=Wording()
        Names of the items and columns in messages.

    Raises
    ------
    ValueError
        When the number of propositions or their names differ from those seen in fit; with
        names on both sides, naming the columns missing and those not seen in fit.

    Warns
    -----
    UserWarning
        When only one of fit and the new traces had proposition names.

    Examples
    --------
    >>> import numpy as np, pandas as pd
    >>> traces = check_traces([pd.DataFrame({"safe": [1], "placed": [0]})])
    >>> check_consistent_traces(traces, 3, np.array(["safe", "picked", "placed"]), "BSI")
    Traceback (most recent call last):
    ...
    ValueError: The feature names should match those that were passed during fit: X lacks the
    proposition 'picked' seen in fit.
    Fitted with: ['safe', 'picked', 'placed']
    Got: ['safe', 'placed']
    """
    fitted, given = feature_names_in, traces.feature_names
    if fitted is not None and given is not None:
        # names on both sides: say which column is missing or new, not only how many there are
        fitted, given = [str(n) for n in fitted], [str(n) for n in given]
        if fitted != given:
            raise ValueError(
                "The feature names should match those that were passed during fit: "
                f"{names_difference(fitted, given, words.unit)}.\n"
                f"Fitted with: {fitted}\nGot: {given}"
            )
    elif traces.n_props != n_features_in:
        raise ValueError(
            f"X has {traces.n_props} features, but {estimator_name} is expecting "
            f"{n_features_in} features as input ({words.unit}s per time step)."
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
