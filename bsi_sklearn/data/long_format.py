"""A long-format frame (``demo_id[, t], prop...[, label]``) split into demonstrations.

The data layer's reading of long-format data: :func:`bsi_sklearn.data.traces.check_traces` splits a
long frame with it, and :mod:`bsi_sklearn.io.long_format` re-exports it for frames and CSV
files, so that the data layer never imports the readers above it.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from bsi_sklearn.data.values import time_column_hint

__all__ = ["traces_from_frame"]


def _show(value):
    """The repr of a value, NumPy scalars shown as Python ones."""
    return repr(value.item() if isinstance(value, np.generic) else value)


def _bad_value(value, csv):
    """How a value that is not 0/1 is named: a missing one as missing, not as ``nan``."""
    if value is None or value is pd.NA or (isinstance(value, (float, np.floating))
                                           and np.isnan(value)):
        # read_csv_rows reports a short row by line; with pandas options under which it
        # cannot count the fields, a short row's last values arrive here as NaN
        return ("is missing (the field is empty or NA, or the row has fewer fields than the "
                "header)" if csv else f"is missing ({_show(value)})")
    return f"has value {_show(value)}"


def traces_from_frame(df, *, demo_col="demo_id", time_col="t", label_col="label",
                      source=None, return_ids=False):
    """Split a long-format frame ``demo_id, t, prop...[, label]`` into traces.

    Parameters
    ----------
    df : DataFrame
        One row per time step of a demonstration. Every column other than ``demo_col``,
        ``time_col`` and ``label_col`` is a proposition (0/1 or boolean).
    demo_col, time_col : str, default="demo_id", "t"
        Demonstration identifier and time step. Demonstrations keep the order of their
        first row; rows are sorted by time, which must be consecutive integers. The time
        column is optional: without it, the rows of a demonstration are its steps, in order.
    label_col : str or None, default="label"
        Label column (constant within a demonstration); absent or ``None``: no labels.
    source : str, default=None
        Name used in error messages (the CSV reader passes the file name; rows are then
        reported by file line).
    return_ids : bool, default=False
        Also return the demonstrations' ids.

    Returns
    -------
    X : list of DataFrame of shape (T_i, n_props)
        Boolean columns named as in ``df``, index ``0..T_i-1``.
    y : ndarray of shape (n_demos,) or None
        The label of each demonstration, as in ``df``; ``None`` without a label column.
    ids : ndarray of shape (n_demos,)
        The ``demo_col`` value of each demonstration (only with ``return_ids=True``).

    Examples
    --------
    >>> import pandas as pd
    >>> df = pd.DataFrame({"demo_id": [0, 0, 1], "t": [0, 1, 0], "a": [1, 0, 1],
    ...                    "b": [0, 1, 1], "label": [1, 1, 0]})
    >>> X, y = traces_from_frame(df)
    >>> [x.shape for x in X], y
    ([(2, 2), (1, 2)], array([1, 0]))
    """
    if not isinstance(df, pd.DataFrame):
        raise ValueError(f"expected a pandas DataFrame, got {type(df).__name__}")
    where = source if source is not None else "frame"
    csv = source is not None

    def row_name(pos):
        return f"line {pos + 2}" if csv else f"row {_show(df.index[pos])}"

    def value_at(pos, prop):
        return (f"{where}, {row_name(pos)}: demonstration {_show(df[demo_col].iat[pos])}, "
                f"step {_show(df[time_col].iat[pos])}, proposition {prop!r}")

    if demo_col not in df.columns:
        raise ValueError(f"{where}: no {demo_col!r} column; columns are {list(df.columns)}")
    if time_col not in df.columns:  # the rows of a demonstration are its steps, in order
        if time_col in (demo_col, label_col):
            raise ValueError(f"{where}: the time column {time_col!r} is also the id or label")
        df = df.assign(**{time_col: df.groupby(demo_col, sort=False).cumcount()})
    has_label = label_col is not None and label_col in df.columns
    props = [c for c in df.columns if c not in (demo_col, time_col, label_col)]
    if not props:
        raise ValueError(f"{where}: no proposition columns besides {demo_col!r}, {time_col!r}")
    if len(df) == 0:
        raise ValueError(f"{where}: no rows (at least one demonstration is required)")
    for col in (demo_col, time_col):
        missing = df[col].isna().to_numpy()
        if missing.any():
            raise ValueError(f"{where}, {row_name(int(np.argmax(missing)))}: missing {col!r}")
    values = df[props]
    arr = values.to_numpy()
    if arr.dtype == object or arr.dtype.kind not in "biuf":
        try:
            arr = values.astype(float).to_numpy()
        except (TypeError, ValueError):
            arr = None
        if arr is None:
            for pos in range(len(df)):
                for k, c in enumerate(props):
                    v = values.iat[pos, k]
                    try:
                        good = float(v) in (0.0, 1.0)
                    except (TypeError, ValueError):
                        good = False
                    if not good:
                        raise ValueError(f"{value_at(pos, c)} {_bad_value(v, csv)}; "
                                         "values must be 0 or 1")
    bad = ~np.isin(arr, (0, 1))
    if bad.any():
        pos, k = map(int, np.argwhere(bad)[0])
        same_demo = (df[demo_col] == df[demo_col].iat[pos]).to_numpy()
        hint = time_column_hint(arr[same_demo, k], props[k])
        raise ValueError(f"{value_at(pos, props[k])} {_bad_value(arr[pos, k], csv)}; values "
                         "must be 0 or 1" + (f" {hint}" if hint else ""))
    arr = arr.astype(bool)
    t_raw = df[time_col].to_numpy()
    try:
        t_val = t_raw.astype(np.float64)
    except (TypeError, ValueError):
        t_val = None
    if t_val is None or not np.all(np.isfinite(t_val)) or np.any(t_val != np.round(t_val)):
        bad_pos = 0
        if t_val is not None:
            bad_pos = int(np.argmax(~np.isfinite(t_val) | (t_val != np.round(t_val))))
        raise ValueError(f"{where}, {row_name(bad_pos)}: time {_show(t_raw[bad_pos])} is not an "
                         "integer")
    t_val = t_val.astype(np.int64)
    codes, uniques = pd.factorize(df[demo_col], sort=False)
    X, y = [], []
    label_values = df[label_col].to_numpy() if has_label else None
    order = np.lexsort((t_val, codes))
    bounds = np.searchsorted(codes[order], np.arange(len(uniques) + 1))
    for d in range(len(uniques)):
        rows = order[bounds[d]:bounds[d + 1]]
        times = t_val[rows]
        dup = np.flatnonzero(np.diff(times) == 0)
        if dup.size:
            raise ValueError(f"{where}, {row_name(int(rows[dup[0] + 1]))}: demonstration "
                             f"{_show(uniques[d])} has time step {_show(times[dup[0]])} twice")
        gap = np.flatnonzero(np.diff(times) != 1)
        if gap.size:
            raise ValueError(f"{where}, {row_name(int(rows[gap[0] + 1]))}: demonstration "
                             f"{_show(uniques[d])} jumps from time {_show(times[gap[0]])} to "
                             f"{_show(times[gap[0] + 1])}; time steps must be consecutive")
        X.append(pd.DataFrame(arr[rows], columns=[str(c) for c in props]))
        if has_label:
            labels = label_values[rows]
            first = labels[0]
            differ = np.flatnonzero(pd.isna(labels) | (labels != first))
            if pd.isna(first):
                differ = np.array([0])
            if differ.size:
                raise ValueError(f"{where}, {row_name(int(rows[differ[0]]))}: the label of "
                                 f"demonstration {_show(uniques[d])} is missing or changes over "
                                 "time; it must be constant")
            y.append(first)
    y = np.asarray(y) if has_label else None
    return (X, y, np.asarray(uniques)) if return_ids else (X, y)
