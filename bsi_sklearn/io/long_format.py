"""Traces in long format, one row per time step (``demo_id, t, prop...``): DataFrames and CSV."""

from __future__ import annotations

import io as _io
import os

import numpy as np
import pandas as pd

from bsi_sklearn.data.long_format import traces_from_frame
from bsi_sklearn.data.traces import check_traces
from bsi_sklearn.io._atomic import write_atomic
from bsi_sklearn.io._csv_rows import read_csv_rows

__all__ = ["traces_from_frame", "traces_to_frame", "read_traces_csv", "write_traces_csv"]


def traces_to_frame(X, y=None, *, feature_names=None, demo_col="demo_id", time_col="t",
                    label_col="label"):
    """Stack traces into a long-format frame ``demo_id, t, prop...[, label]``.

    Parameters
    ----------
    X : demonstrations
        Any format accepted by :func:`bsi_sklearn.data.traces.check_traces`.
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
        changing label, or a row with fewer or more fields than the header.

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
        df = read_csv_rows(path_or_buffer, str(name), **read_csv_kwargs)
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
        Any format accepted by :func:`bsi_sklearn.data.traces.check_traces`.
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
