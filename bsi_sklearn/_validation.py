"""Validation and conversion of demonstrations (traces), labels and proposition roles."""

from __future__ import annotations

import numbers
import warnings
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

__all__ = ["Traces", "check_traces", "check_labels", "Roles", "resolve_roles",
           "NonNumericTraceError"]


class NonNumericTraceError(TypeError, ValueError):
    """A trace holds values that are not numbers (both a TypeError and a ValueError)."""


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


def _is_frame(obj):
    return hasattr(obj, "columns") and hasattr(obj, "to_numpy") and hasattr(obj, "iloc")


@dataclass(frozen=True)
class _Words:
    """What the items and their columns are called in messages."""

    item: str = "demonstration"
    unit: str = "proposition"


_TRACE_WORDS = _Words()


def _frame_names(frame, where):
    cols = list(frame.columns)
    str_cols = [isinstance(c, str) for c in cols]
    if all(str_cols) and cols:
        if len(set(cols)) != len(cols):
            raise ValueError(f"{where} has duplicate column names")
        return np.asarray(cols, dtype=object)
    if any(str_cols):
        raise ValueError(
            f"{where} mixes string and non-string column names; use strings for all columns"
        )
    return None


def _as_numbers(arr, where):
    """Values as a real array (bool kept), or raise naming ``where``."""
    if arr.dtype == bool:
        return arr
    if arr.dtype.kind == "c":
        raise ValueError(f"{where}: Complex data not supported")
    if arr.dtype.kind not in "biuf":
        try:
            arr = arr.astype(np.float64)
        except (TypeError, ValueError) as exc:
            raise NonNumericTraceError(
                f"{where} has non-numeric values (dtype {arr.dtype}): {exc}"
            ) from None
    if arr.dtype.kind == "f":
        bad = ~np.isfinite(arr)
        if bad.any():
            t, p = map(int, np.argwhere(bad)[0])
            raise ValueError(f"{where} has a NaN or infinite value at step {t}, column {p}")
    return arr


def _to_bool(arr, where, binarize):
    """Turn one demonstration's values into uint8 0/1, or raise naming ``where``."""
    arr = _as_numbers(arr, where)
    if arr.dtype == bool:
        return arr.astype(np.uint8)
    if binarize is not None:
        return (arr > binarize).astype(np.uint8)
    bad = (arr != 0) & (arr != 1)
    if bad.any():
        t, p = map(int, np.argwhere(bad)[0])
        raise ValueError(
            f"{where} has value {arr[t, p].item()!r} at step {t}, proposition {p}; traces must "
            "be 0/1 or boolean (set binarize=<threshold> to threshold numeric data)"
        )
    return arr.astype(np.uint8)


def _to_float(arr, where, binarize=None):
    """Turn one sequence's values into finite float64 (numeric sequences, not traces)."""
    return np.asarray(_as_numbers(arr, where), dtype=np.float64)


def check_traces(X, *, binarize=None, estimator_name="estimator", numeric=False,
                 words=_TRACE_WORDS):
    """Validate demonstrations and stack them for the kernels.

    Parameters
    ----------
    X : list of array-like or DataFrame, 3-D array or 2-D array
        See DESIGN section 1: a list (or tuple) of ``(T_i, n_props)`` traces, a list of
        DataFrames, a 3-D array ``(n_demos, T, n_props)`` or a 2-D array ``(n_demos, n_props)``
        whose rows are traces of length one (a single DataFrame is read the same way).
    binarize : float or None, default=None
        When set, values ``> binarize`` become true; otherwise values must be 0/1 or boolean.
    estimator_name : str
        Used in messages.
    numeric : bool, default=False
        Keep finite real values as float64 instead of requiring booleans (the sequence models
        of ``baselines`` share this validation).
    words : _Words
        Names of the items and columns in messages.

    Returns
    -------
    traces : Traces
    """
    if binarize is not None and (
        not isinstance(binarize, numbers.Real) or isinstance(binarize, bool)
        or not np.isfinite(binarize)
    ):
        raise ValueError(f"binarize must be None or a finite number, got {binarize!r}")
    convert = _to_float if numeric else _to_bool
    items = words.item + "s"
    if X is None:
        raise ValueError(f"{estimator_name} expects {items}, got None")
    if hasattr(X, "tocsr") or hasattr(X, "to_dense") and not _is_frame(X):
        raise TypeError(
            f"{estimator_name} does not support sparse input; pass dense arrays "
            "(e.g. X.toarray())"
        )
    names = None
    if _is_frame(X):
        names = _frame_names(X, "the DataFrame")
        X = X.to_numpy()
    if isinstance(X, (list, tuple)):
        if len(X) == 0:
            raise ValueError(f"{estimator_name} needs at least one {words.item}, got 0")
        if not _is_frame(X[0]) and np.ndim(X[0]) == 1:
            # Nested lists of scalars: the 2-D format (each row a trace of length one).
            try:
                arr = np.asarray(X)
            except ValueError:
                arr = None
            if arr is not None and arr.ndim == 2 and arr.dtype != object:
                return check_traces(arr, binarize=binarize, estimator_name=estimator_name,
                                    numeric=numeric, words=words)
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
        return _stack_rows(convert(arr, "X", binarize), names, words)
    hint = (" Reshape your data: X.reshape(1, -1) for one trace of length one, or wrap a "
            "(T, n_props) trace in a list." if arr.ndim == 1 else "")
    raise ValueError(
        f"{items} must be a list of 2-D arrays, a 3-D array (n_{items}, T, n_{words.unit}s) "
        f"or a 2-D array (n_{items}, n_{words.unit}s); got an array with {arr.ndim} "
        f"dimension(s).{hint}"
    )


def _stack_rows(rows, names, words):
    offsets = np.arange(rows.shape[0] + 1, dtype=np.int64)
    return Traces(np.ascontiguousarray(rows), offsets, names)


def _stack_list(items, convert, binarize, words):
    arrays, names, n_props = [], None, None
    unit = words.unit
    for i, item in enumerate(items):
        where = f"{words.item} {i}"
        if _is_frame(item):
            item_names = _frame_names(item, where)
            if i == 0:
                names = item_names
            elif (names is None) != (item_names is None) or (
                names is not None and list(names) != list(item_names)
            ):
                raise ValueError(
                    f"{where} has columns {list(item.columns)}, but {words.item} 0 has "
                    f"{list(names) if names is not None else 'no string names'}"
                )
            arr = item.to_numpy()
        else:
            if i > 0 and names is not None:
                raise ValueError(f"{where} is not a DataFrame, but {words.item} 0 is")
            try:
                arr = np.asarray(item)
            except ValueError as exc:
                raise ValueError(f"{where} is ragged: {exc}") from None
        if arr.dtype == object and arr.ndim == 1:
            raise ValueError(f"{where} is ragged: its time steps have different lengths")
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
        arrays.append(convert(arr, where, binarize))
    lengths = np.array([a.shape[0] for a in arrays], dtype=np.int64)
    offsets = np.zeros(len(arrays) + 1, dtype=np.int64)
    np.cumsum(lengths, out=offsets[1:])
    return Traces(np.ascontiguousarray(np.concatenate(arrays, axis=0)), offsets, names)


def check_consistent_traces(traces, n_features_in, feature_names_in, estimator_name,
                            words=_TRACE_WORDS):
    """Check that traces given after fit have the propositions seen in fit."""
    if traces.n_props != n_features_in:
        raise ValueError(
            f"X has {traces.n_props} features, but {estimator_name} is expecting "
            f"{n_features_in} features as input ({words.unit}s per time step)."
        )
    fitted, given = feature_names_in, traces.feature_names
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


def check_labels(y, n_demos, pos_label=None):
    """Validate labels; return ``(y01, classes)`` with ``y01`` in {0, 1}.

    ``y=None`` means every demonstration is acceptable (positive-only learning).
    """
    if y is None:
        return np.ones(n_demos, dtype=np.int8), np.array([0, 1])
    y_arr = np.asarray(y)
    if y_arr.ndim == 2 and y_arr.shape[1] == 1:
        warnings.warn(
            "A column-vector y was passed when a 1d array was expected; it is raveled.",
            _data_conversion_warning(),
            stacklevel=3,
        )
        y_arr = y_arr.ravel()
    if y_arr.ndim != 1:
        raise ValueError(f"y must be 1-D (one label per demonstration), got shape {y_arr.shape}")
    if y_arr.shape[0] != n_demos:
        raise ValueError(
            f"y has {y_arr.shape[0]} labels but there are {n_demos} demonstrations"
        )
    if y_arr.dtype.kind == "f" and not np.isfinite(y_arr).all():
        raise ValueError(
            f"y has a NaN or infinite label at demonstration {int(np.argmin(np.isfinite(y_arr)))}"
        )
    values = np.unique(y_arr)
    if y_arr.dtype.kind == "f" and np.any(values != np.round(values)):
        raise ValueError(
            "Unknown label type: continuous. BSIClassifier expects binary labels "
            "(acceptable = 1, unacceptable = 0)"
        )
    if len(values) > 2:
        raise ValueError(
            "Only binary classification is supported. The type of the target is multiclass: "
            f"y has {len(values)} classes {values.tolist()[:10]}, while BSI separates "
            "acceptable from unacceptable demonstrations"
        )
    if pos_label is not None:
        if pos_label not in values.tolist():
            if len(values) == 2:
                raise ValueError(
                    f"pos_label={pos_label!r} is not among the labels {values.tolist()}"
                )
            raise ValueError(
                f"y has the single label {values[0]!r}, which is not pos_label={pos_label!r}; "
                "at least one acceptable demonstration is required"
            )
        y01 = (y_arr == pos_label).astype(np.int8)
        if len(values) == 2:
            classes = values
            if classes[1] != pos_label:
                classes = classes[::-1].copy()
        else:
            classes = np.array([None, pos_label], dtype=object)
        return y01, classes
    if y_arr.dtype == bool:
        return y_arr.astype(np.int8), np.array([False, True])
    if not set(values.tolist()) <= {0, 1}:
        raise ValueError(
            f"labels must be 0/1 (or booleans); got {values.tolist()}. Pass pos_label to name "
            "the acceptable label"
        )
    y01 = y_arr.astype(np.int8)
    if not y01.any():
        raise ValueError(
            "y has only unacceptable (0) demonstrations; BSI needs at least one acceptable (1) "
            "demonstration"
        )
    return y01, np.array([0, 1], dtype=y_arr.dtype if y_arr.dtype.kind in "iu" else int)


def _data_conversion_warning():
    from sklearn.exceptions import DataConversionWarning

    return DataConversionWarning


@dataclass(frozen=True)
class Roles:
    """Proposition roles resolved to column indices.

    Attributes
    ----------
    global_idx : ndarray of int64
        Column of every global candidate (the set T).
    subtask_idx : ndarray of int64
        Column of every subtask proposition omega_w (the set Omega).
    condition_idx : ndarray of int64
        Column of each subtask's condition pi_w, or -1 when pi_w = true.
    names : list
        Identifier of every column, as used in specifications.
    """

    global_idx: np.ndarray
    subtask_idx: np.ndarray
    condition_idx: np.ndarray
    names: list

    @property
    def n_globals(self):
        """``|T|``."""
        return len(self.global_idx)

    @property
    def n_subtasks(self):
        """``|Omega|``."""
        return len(self.subtask_idx)

    def global_names(self):
        """Identifiers of the global candidates."""
        return [self.names[i] for i in self.global_idx]

    def subtask_names(self):
        """Identifiers of the subtasks."""
        return [self.names[i] for i in self.subtask_idx]

    def condition_names(self):
        """Subtask identifier -> condition identifier (only subtasks with a condition)."""
        return {
            self.names[s]: self.names[c]
            for s, c in zip(self.subtask_idx, self.condition_idx)
            if c >= 0
        }


def _resolve_one(ident, names, param):
    n = len(names)
    if isinstance(ident, (bool, np.bool_)):
        raise ValueError(f"{param}: {ident!r} is not a proposition name or index")
    if isinstance(ident, (numbers.Integral, np.integer)):
        if not 0 <= int(ident) < n:
            raise ValueError(
                f"{param}: proposition index {int(ident)} is out of range for {n} propositions"
            )
        return int(ident)
    try:
        return names.index(ident)
    except ValueError:
        raise ValueError(
            f"{param}: unknown proposition {ident!r}; known propositions are "
            f"{names[:20]}{' ...' if n > 20 else ''}"
        ) from None


def _resolve_list(value, names, param):
    if value is None:
        return np.arange(len(names), dtype=np.int64)
    if isinstance(value, (str, bytes)) or not hasattr(value, "__iter__"):
        raise ValueError(
            f"{param} must be None or a list of proposition names or indices, got {value!r}"
        )
    idx = [_resolve_one(v, names, param) for v in value]
    seen = set()
    for v, i in zip(value, idx):
        if i in seen:
            raise ValueError(f"{param}: proposition {v!r} is listed more than once")
        seen.add(i)
    return np.asarray(idx, dtype=np.int64)


def resolve_roles(global_candidates, subtasks, conditions, n_props, feature_names=None):
    """Resolve role parameters (names or indices) to column indices, with clear errors."""
    names = list(feature_names) if feature_names is not None else list(range(n_props))
    g = _resolve_list(global_candidates, names, "global_candidates")
    s = _resolve_list(subtasks, names, "subtasks")
    cond = np.full(len(s), -1, dtype=np.int64)
    if conditions is not None:
        if not isinstance(conditions, Mapping):
            raise ValueError(
                f"conditions must be None or a mapping subtask -> condition proposition, got "
                f"{type(conditions).__name__}"
            )
        position = {int(c): k for k, c in enumerate(s)}
        for w, c in conditions.items():
            wi = _resolve_one(w, names, "conditions")
            if wi not in position:
                raise ValueError(f"conditions: {w!r} is not one of the subtasks")
            if c is None:
                continue
            cond[position[wi]] = _resolve_one(c, names, f"conditions[{w!r}]")
    return Roles(g, s, cond, names)
