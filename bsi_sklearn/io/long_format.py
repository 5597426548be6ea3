"""Traces in long format, one row per time step (``demo_id, t, prop...``): DataFrames and CSV."""

from __future__ import annotations

import io as _io
import os

import numpy as np
import pandas as pd

from bsi_sklearn.io._atomic import write_atomic
from bsi_sklearn.traces import check_traces

__all__ = ["traces_from_frame", "traces_to_frame", "read_traces_csv", "write_traces_csv"]


def _show(value):
    """The repr of a value, NumPy scalars shown as Python ones."""
    return repr(value.item() if isinstance(value, np.generic) else value)


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
                        raise ValueError(f"{value_at(pos, c)} has value {_show(v)}; "
                                         "values must be 0 or 1")
    bad = ~np.isin(arr, (0, 1))
    if bad.any():
        pos, k = map(int, np.argwhere(bad)[0])
        raise ValueError(f"{value_at(pos, props[k])} has value {_show(arr[pos, k])}; values "
                         "must be 0 or 1")
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


def traces_to_frame(X, y=None, *, feature_names=None, demo_col="demo_id", time_col="t",
                    label_col="label"):
    """Stack traces into a long-format frame ``demo_id, t, prop...[, label]``.

    Parameters
    ----------
    X : demonstrations
        Any format accepted by :func:`bsi_sklearn.traces.check_traces`.
    y : array-like of shape (n_demos,), default=None
        Labels, written to ``label_col`` when given.
    feature_names : sequence of str, default=None
        Proposition column names; default the DataFrame columns, else ``x0, x1, ...``.
    demo_col, time_col, label_col : str
        Names of the identifier, time and label columns.

    Returns
    -------
    frame : DataFrame
        Demonstration ids ``0..n_demos-1``, times ``0..T_i-1``, 0/1 propositions (int8).

    Examples
    --------
    >>> import numpy as np
    >>> traces_to_frame([np.array([[1, 0], [0, 1]]), np.array([[1, 1]])], y=[1, 0])
       demo_id  t  x0  x1  label
    0        0  0   1   0      1
    1        0  1   0   1      1
    2        1  0   1   1      0
    """
    traces = check_traces(X, estimator_name="traces_to_frame")
    if feature_names is None:
        feature_names = (list(traces.feature_names) if traces.feature_names is not None
                         else [f"x{i}" for i in range(traces.n_props)])
    feature_names = [str(n) for n in feature_names]
    if len(feature_names) != traces.n_props:
        raise ValueError(f"feature_names has {len(feature_names)} names for "
                         f"{traces.n_props} propositions")
    reserved = {demo_col, time_col} | ({label_col} if y is not None else set())
    clash = sorted(set(feature_names) & reserved)
    if clash:
        raise ValueError(f"proposition names {clash} clash with the id/time/label columns")
    lengths = traces.lengths
    frame = pd.DataFrame({
        demo_col: np.repeat(np.arange(traces.n_demos), lengths),
        time_col: np.arange(traces.data.shape[0]) - np.repeat(traces.offsets[:-1], lengths),
    })
    props = pd.DataFrame(traces.data.astype(np.int8), columns=feature_names)
    frame = pd.concat([frame, props], axis=1)
    if y is not None:
        y = np.asarray(y)
        if y.shape != (traces.n_demos,):
            raise ValueError(f"y must hold one label per demonstration ({traces.n_demos}), "
                             f"got shape {y.shape}")
        frame[label_col] = np.repeat(y, lengths)
    return frame


def read_traces_csv(path_or_buffer, *, demo_col="demo_id", time_col="t", label_col="label",
                    return_ids=False, **read_csv_kwargs):
    r"""Read long-format traces ``demo_id[, t], prop...[, label]`` from a CSV file.

    Parameters
    ----------
    path_or_buffer : str, path-like or file-like
        Anything :func:`pandas.read_csv` reads.
    demo_col, time_col, label_col : str
        Column names (see :func:`traces_from_frame`); the time and label columns are
        optional (without time, a demonstration's rows are its steps, in order).
    return_ids : bool, default=False
        Also return the demonstrations' ids (the ``demo_col`` values).
    **read_csv_kwargs
        Passed to :func:`pandas.read_csv` (e.g. ``sep``).

    Returns
    -------
    X : list of DataFrame
    y : ndarray or None
    ids : ndarray
        Only with ``return_ids=True``.

    Raises
    ------
    ValueError
        Naming the file and the 1-based line of a bad value, duplicate or missing time step,
        or changing label.

    Examples
    --------
    >>> import io
    >>> X, y = read_traces_csv(io.StringIO("demo_id,t,a,label\n7,0,1,1\n7,1,0,1\n"))
    >>> X[0]["a"].tolist(), y
    ([True, False], array([1]))
    """
    name = (os.fspath(path_or_buffer) if isinstance(path_or_buffer, (str, os.PathLike))
            else getattr(path_or_buffer, "name", "<csv buffer>"))
    try:
        df = pd.read_csv(path_or_buffer, **read_csv_kwargs)
    except (pd.errors.ParserError, pd.errors.EmptyDataError) as exc:
        raise ValueError(f"{name}: {exc}") from None
    return traces_from_frame(df, demo_col=demo_col, time_col=time_col, label_col=label_col,
                             source=str(name), return_ids=return_ids)


def write_traces_csv(X, y, path_or_buffer=None, *, feature_names=None, demo_col="demo_id",
                     time_col="t", label_col="label"):
    """Write traces in the long CSV format read by :func:`read_traces_csv`.

    Parameters
    ----------
    X : demonstrations
        Any format accepted by :func:`bsi_sklearn.traces.check_traces`.
    y : array-like of shape (n_demos,) or None
        Labels (a ``label`` column), or ``None`` for none.
    path_or_buffer : str, path-like, file-like or None, default=None
        Destination; ``None`` returns the text.
    feature_names, demo_col, time_col, label_col
        See :func:`traces_to_frame`.

    Returns
    -------
    text : str or None
        The CSV text when ``path_or_buffer`` is ``None``.

    Examples
    --------
    >>> import numpy as np
    >>> print(write_traces_csv([np.array([[1, 0], [0, 1]])], [1]), end="")
    demo_id,t,x0,x1,label
    0,0,1,0,1
    0,1,0,1,1
    """
    if isinstance(y, (str, os.PathLike, _io.IOBase)):
        raise ValueError("y must be labels or None; pass the destination as path_or_buffer")
    frame = traces_to_frame(X, y, feature_names=feature_names, demo_col=demo_col,
                            time_col=time_col, label_col=label_col)
    if isinstance(path_or_buffer, (str, os.PathLike)):
        write_atomic(path_or_buffer, frame.to_csv(index=False))
        return None
    return frame.to_csv(path_or_buffer, index=False)
