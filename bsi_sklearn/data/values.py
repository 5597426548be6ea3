"""The values of one demonstration: conversion to 0/1 (or floats) and messages that say where.

Private helpers of :mod:`bsi_sklearn.data.traces` (and :func:`trace_columns`, one trace by column
name, of the specification and its automaton). Every message names the demonstration, the step
and the proposition: by its DataFrame column name when there is one, by its index otherwise.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = [
    "NonNumericTraceError",
    "Place",
    "frame_names",
    "names_difference",
    "ragged_error",
    "ragged_rows_error",
    "to_bool",
    "time_column_hint",
    "to_float",
    "trace_columns",
]


class NonNumericTraceError(TypeError, ValueError):
    """A trace holds values that are not numbers (both a TypeError and a ValueError)."""


@dataclass(frozen=True)
class Place:
    """Where a block of values comes from, for messages.

    Attributes
    ----------
    item : str
        ``"demonstration"`` (or ``"sequence"``).
    unit : str
        ``"proposition"`` (or ``"feature"``).
    index : int or None
        The demonstration of the block; ``None`` when the block is a 2-D array whose rows are
        demonstrations of length one.
    names : sequence of str or None
        Column names, when the input carried them.

    Examples
    --------
    >>> Place("demonstration", "proposition", 2, ["safe", "done"]).at(4, 1)
    "demonstration 2, step 4, proposition 'done'"
    >>> Place("demonstration", "proposition", None, None).at(4, 1)
    'demonstration 4, step 0, proposition 1'
    """

    item: str
    unit: str
    index: int | None
    names: object = None

    def column(self, p):
        """The proposition ``p``: its name, or its index when the input had no names."""
        if self.names is not None:
            return f"{self.unit} {str(self.names[p])!r}"
        return f"{self.unit} {p}"

    def at(self, t, p):
        """``"demonstration i, step t, proposition 'name'"``."""
        if self.index is None:  # rows are demonstrations of length one
            return f"{self.item} {t}, step 0, {self.column(p)}"
        return f"{self.item} {self.index}, step {t}, {self.column(p)}"

    def __str__(self):
        return f"{self.item} {self.index}" if self.index is not None else "X"


def frame_names(frame, where):
    """String column names of a DataFrame (``None`` when none are strings), or raise."""
    cols = list(frame.columns)
    str_cols = [isinstance(c, str) for c in cols]
    if all(str_cols) and cols:
        if len(set(cols)) != len(cols):
            dup = sorted({c for c in cols if cols.count(c) > 1})
            raise ValueError(f"{where} has duplicate column names {dup}")
        return np.asarray(cols, dtype=object)
    if any(str_cols):
        raise ValueError(
            f"{where} mixes string and non-string column names; use strings for all columns"
        )
    return None


def names_difference(expected, given, unit, subject="X", reference="fit"):
    """What differs between two lists of column names, in words (for a message).

    Examples
    --------
    >>> names_difference(["a", "b", "c"], ["a", "c", "z"], "proposition")
    "X lacks the proposition 'b' seen in fit; X has the proposition 'z' not seen in fit"
    >>> names_difference(["a", "b"], ["a"], "proposition", "demonstration 2", "demonstration 0")
    "demonstration 2 lacks the proposition 'b' seen in demonstration 0"
    """
    def listed(names):
        if len(names) == 1:
            return f"the {unit} {names[0]!r}"
        return f"the {unit}s {', '.join(map(repr, names))}"

    seen, now = set(expected), set(given)
    missing = [n for n in expected if n not in now]
    unseen = [n for n in given if n not in seen]
    parts = []
    if missing:
        parts.append(f"{subject} lacks {listed(missing)} seen in {reference}")
    if unseen:
        parts.append(f"{subject} has {listed(unseen)} not seen in {reference}")
    if parts:
        return "; ".join(parts)
    order = f"{subject} has the {unit}s of {reference} in another order"
    if reference == "fit":
        order += " (select them in fit's order: df[list(feature_names_in_)])"
    return order


def _show(value):
    return repr(value.item() if isinstance(value, np.generic) else value)


def _first_non_number(arr):
    """``(t, p, value, error)`` of the first value ``float`` cannot read."""
    for (t, p), value in np.ndenumerate(arr):
        try:
            float(value)
        except (TypeError, ValueError) as exc:
            return t, p, value, exc
    return None


def _as_numbers(arr, place):
    """Values as a real array (bool kept), or raise naming the place."""
    if arr.dtype == bool:
        return arr
    if arr.dtype.kind == "c":
        raise ValueError(f"{place}: Complex data not supported")
    if arr.dtype.kind not in "biuf":
        try:
            arr = arr.astype(np.float64)
        except (TypeError, ValueError) as exc:
            found = _first_non_number(arr)
            if found is None:
                raise NonNumericTraceError(
                    f"{place} has non-numeric values (dtype {arr.dtype}): {exc}"
                ) from None
            t, p, value, err = found
            raise NonNumericTraceError(
                f"{place.at(t, p)} has the non-numeric value {_show(value)} ({err})"
            ) from None
    if arr.dtype.kind == "f":
        bad = ~np.isfinite(arr)
        if bad.any():
            t, p = map(int, np.argwhere(bad)[0])
            raise ValueError(f"{place.at(t, p)} is {_show(arr[t, p])}: a NaN or infinite "
                             "value; every step needs a finite value")
    return arr


def to_bool(arr, place, binarize):
    """Turn one demonstration's values into uint8 0/1, or raise naming the place."""
    arr = _as_numbers(arr, place)
    if arr.dtype == bool:
        return arr.astype(np.uint8)
    if binarize is not None:
        return (arr > binarize).astype(np.uint8)
    bad = (arr != 0) & (arr != 1)
    if bad.any():
        t, p = map(int, np.argwhere(bad)[0])
        name = place.names[p] if place.names is not None else None
        advice = time_column_hint(arr[:, p], name) or (
            "(set binarize=<threshold> to threshold numeric data)")
        raise ValueError(
            f"{place.at(t, p)} has value {arr[t, p].item()!r}; traces must be 0/1 or boolean "
            f"{advice}"
        )
    return arr.astype(np.uint8)


_TIME_NAMES = {"t", "time", "times", "timestamp", "timestamps", "ts", "step", "steps",
               "date", "datetime", "frame", "clock", "seconds", "secs", "ms"}


def time_column_hint(values, name=None):
    """Advice when a non-0/1 column looks like time rather than a proposition, else "".

    A column looks like time when its name says so (``time``, ``timestamp``, ``step``...) or
    its values increase at every step of a demonstration of two steps or more.

    Examples
    --------
    >>> time_column_hint([0.5, 1.0, 1.5], "x")[:44]
    '(the column looks like a time stamp, not a p'
    >>> time_column_hint([3, 0, 7], "speed")
    ''
    """
    try:
        v = np.asarray(values, dtype=float)
    except (TypeError, ValueError):
        return ""
    named = name is not None and str(name).strip().lower() in _TIME_NAMES
    rising = v.ndim == 1 and len(v) >= 2 and bool(np.all(np.diff(v) > 0))
    if not (named or rising):
        return ""
    return ("(the column looks like a time stamp, not a proposition: drop it, or in a "
            "long-format frame or CSV name the step column 't'; thresholding it with binarize "
            "would make it a meaningless proposition)")


def to_float(arr, place, binarize=None):
    """Turn one sequence's values into finite float64 (numeric sequences, not traces)."""
    return np.asarray(_as_numbers(arr, place), dtype=np.float64)


def ragged_error(item, where, unit):
    """A ValueError saying which step of a nested list has a different length."""
    try:
        lengths = [len(step) for step in item]
    except TypeError:
        return ValueError(f"{where} is ragged: it mixes time steps and single values")
    t = next((i for i, n in enumerate(lengths) if n != lengths[0]), None)
    if t is None:
        return ValueError(f"{where} is ragged: its values are nested to different depths")
    return ValueError(f"{where} is ragged: step {t} has {lengths[t]} {unit}s, step 0 has "
                      f"{lengths[0]}")


def ragged_rows_error(rows, estimator_name, item, unit):
    """A ValueError for a list of lists (the 2-D format) whose rows differ in length."""
    lengths = [len(r) if isinstance(r, (list, tuple)) else -1 for r in rows]
    k = next((i for i, n in enumerate(lengths) if n != lengths[0]), 0)
    what = (f"has {lengths[k]} {unit}s, row 0 has {lengths[0]}" if lengths[k] >= 0
            else "is not a list of numbers")
    return ValueError(f"{estimator_name} got a list of lists (scikit-learn's 2-D format, every "
                      f"row a {item} of length one) whose row {k} {what}")


def trace_columns(trace, feature_names):
    """One trace as a boolean array and its column names (name -> index, or None).

    Parameters
    ----------
    trace : array-like of shape (T, n_props) or pandas.DataFrame
    feature_names : sequence or None
        Column names; a DataFrame's columns when None.

    Returns
    -------
    columns : dict or None
        Column name -> index, when the trace has names.
    arr : ndarray of shape (T, n_props), bool

    Raises
    ------
    ValueError
        For a trace that is not a non-empty 2-D 0/1 array, or names of the wrong length.
    """
    if hasattr(trace, "columns") and hasattr(trace, "to_numpy"):
        names = list(trace.columns) if feature_names is None else list(feature_names)
        arr = trace.to_numpy()
    else:
        names = None if feature_names is None else list(feature_names)
        arr = np.asarray(trace)
    if arr.ndim != 2 or arr.shape[0] < 1:
        raise ValueError(f"a trace must be a non-empty 2-D array (T, n_props), got {arr.shape}")
    if arr.dtype.kind == "f" and np.isnan(arr).any():
        raise ValueError("the trace contains NaN")
    if not np.isin(arr, (0, 1)).all():
        raise ValueError("the trace has values other than 0/1 (booleans)")
    arr = arr.astype(bool)
    if names is not None:
        if len(names) != arr.shape[1]:
            raise ValueError(
                f"feature_names has {len(names)} entries for a trace of {arr.shape[1]} columns"
            )
        return {n: i for i, n in enumerate(names)}, arr
    return None, arr
