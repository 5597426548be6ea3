"""Event logs (XES, CSV, pm4py's event DataFrames) read into cases of ordered events and labels.

An event log is cases of events: a case id, an activity and (optionally) a timestamp per event,
any other attributes, and a label per case, given as a trace attribute or as a separate table.
:func:`read_event_log` returns the cases as a list (one DataFrame of events per case, in time
order), the labels as 0/1 and the case ids; :class:`~bsi_sklearn.io.EventLogEncoder` turns the
cases into the traces BSI learns from (``docs/event-logs.md``).
The cases' labels (a case attribute or a table, to 0/1) are read by ``_case_labels.py``.
"""

from __future__ import annotations

import gc
import os
from contextlib import contextmanager
from typing import NamedTuple

import numpy as np
import pandas as pd

from bsi_sklearn.io._case_labels import _binary, _case_constant, _table_labels
from bsi_sklearn.io._csv_rows import read_csv_rows
from bsi_sklearn.io._xes import read_xes_columns

__all__ = ["ACTIVITY", "CASE_ID", "TIMESTAMP", "EventLog", "read_event_log", "order_events"]

#: pm4py's column names: the case id, the activity and the timestamp of an event.
CASE_ID = "case:concept:name"
ACTIVITY = "concept:name"
TIMESTAMP = "time:timestamp"
_CASE = "__case__"
_EVENT = "__event__"  # an event's position in its case in the source (for messages)


class EventLog(NamedTuple):
    """What :func:`read_event_log` returns: ``cases, y, case_ids = read_event_log(...)``.

    Attributes
    ----------
    cases : list of DataFrame
        One DataFrame per case: its events in time order, the activity as ``concept:name``,
        ``time:timestamp`` when the log has timestamps, then the event attributes.
    y : ndarray of shape (n_cases,) of int, or None
        1 for acceptable cases, 0 for the others; ``None`` when no label was asked for.
    case_ids : ndarray of shape (n_cases,)
        The cases' ids, in the order of ``cases`` (order of first appearance in the source).
    """

    cases: list
    y: np.ndarray | None
    case_ids: np.ndarray


def _name(source):
    if isinstance(source, (str, os.PathLike)):
        return os.fspath(source)
    return "the event DataFrame"


def _format(source, fmt):
    if fmt is not None:
        if fmt not in ("xes", "csv"):
            raise ValueError(f"format must be None, 'xes' or 'csv', got {fmt!r}")
        return fmt
    name = os.fspath(source).lower()
    return "xes" if name.endswith((".xes", ".xes.gz")) else "csv"


def read_event_log(source, *, label=None, pos_label=None, labels=None, case_id=None,
                   activity=None, timestamp=None, format=None):
    """Read an event log into cases (events in time order), 0/1 labels and case ids.

    Parameters
    ----------
    source : str, path-like or DataFrame
        An XES file (``.xes``, or gzip-compressed ``.xes.gz``; streamed, never held as XML),
        a CSV file with one row per event, or a pandas event DataFrame (one row per event).
    label : str, default=None
        The trace attribute that holds each case's label: in XES the trace attribute ``label``
        (pm4py's ``case:<label>``); in a CSV file or DataFrame the column ``case:<label>``, or
        ``label`` itself, constant within a case.
    pos_label : object, default=None
        The label value of acceptable cases. Labels that are 0/1 or True/False need none; any
        other pair of values does. A string also matches a label whose text it is (``"1"``
        an integer 1, ``"true"`` a boolean true).
    labels : Series, mapping or str or path-like, default=None
        The labels as a separate table instead of ``label``: case id -> label (a Series
        indexed by case id, a dict), or a CSV file whose case-id column is named like the
        log's (else its first column) and whose label column is ``label`` when given (else
        its only other column). Every case needs exactly one label, and every id of the table
        must be a case of the log.
    case_id, activity, timestamp : str, default=None
        Column names of the case id, the activity and the timestamp (pm4py's by default:
        ``case:concept:name``, ``concept:name``, ``time:timestamp``). In XES, ``case:<key>``
        names a trace attribute and ``<key>`` an event attribute.
    format : {None, "xes", "csv"}, default=None
        How to read a path: ``None`` decides by its name (``.xes`` / ``.xes.gz`` is XES,
        anything else CSV).

    Returns
    -------
    log : EventLog
        ``(cases, y, case_ids)``. ``cases[i]`` is a DataFrame of case ``case_ids[i]``'s
        events ordered by timestamp (a stable sort: ties keep the source's order), with the
        columns ``concept:name`` (the activity), ``time:timestamp`` (when there is one) and
        the event attributes; case attributes (``case:`` columns, the label) are left out.
        Cases come in the order of their first event in the source.

    Raises
    ------
    ValueError
        Naming the case (by id) and, where there is one, the event (its position in the case,
        in source order, from 0) and the column: a case without events, without an activity or
        a label, a label that differs within a case or a third label value, a timestamp that
        cannot be read, a case where some events have a timestamp and others do not, two XES
        traces with the same ``concept:name``.

    Notes
    -----
    Timestamps: a case whose events all lack a timestamp keeps the source's order; a case
    where only some lack one is an error (where its untimed events belong is unknown). Text
    timestamps are read by :func:`pandas.to_datetime` (ISO 8601 first); when they carry
    different UTC offsets they are compared in UTC. Numeric timestamps are ordered as numbers.

    Examples
    --------
    >>> import pandas as pd
    >>> df = pd.DataFrame({
    ...     "case:concept:name": ["c1", "c1", "c2", "c2"],
    ...     "concept:name": ["pay", "order", "order", "ship"],
    ...     "time:timestamp": pd.to_datetime(["2024-01-02", "2024-01-01",
    ...                                       "2024-01-01", "2024-01-03"]),
    ...     "case:ok": [1, 1, 0, 0]})
    >>> cases, y, case_ids = read_event_log(df, label="ok")
    >>> [c["concept:name"].tolist() for c in cases], y.tolist(), case_ids.tolist()
    ([['order', 'pay'], ['order', 'ship']], [1, 0], ['c1', 'c2'])
    """
    case_id = CASE_ID if case_id is None else case_id
    activity = ACTIVITY if activity is None else activity
    explicit_time = timestamp is not None
    timestamp = TIMESTAMP if timestamp is None else timestamp
    if pos_label is not None and label is None and labels is None:
        raise ValueError("pos_label is given but no label: name the trace attribute with "
                         "label= or pass the labels table as labels=")
    if label is not None and labels is not None:
        raise ValueError("give the labels either as a trace attribute (label=) or as a "
                         "table (labels=), not both")
    with _no_gc():
        return _read(source, label, pos_label, labels, case_id, activity, timestamp,
                     explicit_time, format)


@contextmanager
def _no_gc():
    """Pause the cyclic garbage collector while a log is read, then restore it as it was.

    Reading makes millions of strings and small arrays and no cycles; the collector's passes
    over them cost 10-50% of the time (most in building one DataFrame per case).
    """
    was = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if was:
            gc.enable()


def _read(source, label, pos_label, labels, case_id, activity, timestamp, explicit_time,
          format):
    name = _name(source)
    if hasattr(source, "columns"):
        events, ids, case_table = _from_frame(source, case_id, name)
    elif _format(source, format) == "xes":
        events, ids, case_table = _from_xes(source, case_id, name)
    else:
        events, ids, case_table = _from_csv(source, case_id, activity, timestamp, name)
    where = _Where(ids, name)
    if timestamp not in events.columns:
        if explicit_time:
            raise ValueError(f"{name}: no timestamp column {timestamp!r}; the columns are "
                             f"{_listed(events)}")
        timestamp = None
    events, starts = order_events(events, activity, timestamp, where)
    y, label_col = None, None
    if label is not None:
        values, label_col = case_table(label, events, starts, where)
        y = _binary(values, pos_label, where)
    elif labels is not None:
        y = _binary(_table_labels(labels, ids, case_id, where), pos_label, where)
    drop = [] if label_col is None else [label_col]
    return EventLog(case_frames(events.drop(columns=drop), starts, activity, timestamp), y,
                    ids)


class _Where:
    """Names cases and events in messages: ``case 'c7', event 2``."""

    def __init__(self, ids, source):
        self.ids = ids
        self.source = source

    def case(self, i):
        return f"{self.source}: case {self.ids[int(i)]!r}"

    def event(self, i, k):
        return f"{self.case(i)}, event {int(k)}"


def _listed(events):
    return [c for c in events.columns if c not in (_CASE, _EVENT)]


# ---------------------------------------------------------------- sources
def _from_xes(path, case_id, name):
    cols = read_xes_columns(path, case_name="case")
    key = case_id.removeprefix("case:")
    ids = cols.traces.get(key)
    if ids is None:
        raise ValueError(f"{name}: the traces have no attribute {key!r} to name the cases "
                         f"(trace attributes: {sorted(cols.traces)})")
    ids = np.asarray(ids, dtype=object)
    missing = pd.isna(ids)
    if missing.any():
        raise ValueError(f"{name}: trace {int(np.argmax(missing))} (counted from 0) has no "
                         f"{key!r}: every case needs an id")
    _check_unique(ids, name)

    def case_table(label, events, starts, where):
        key = label.removeprefix("case:")
        if key not in cols.traces:
            raise ValueError(f"{name}: the traces have no attribute {key!r} for the label "
                             f"(trace attributes: {sorted(cols.traces)})")
        return np.asarray(cols.traces[key], dtype=object), None

    return cols.events, ids, case_table


def _check_unique(ids, name):
    uniq, first, counts = np.unique(ids.astype(str), return_index=True, return_counts=True)
    if (counts > 1).any():
        dup = ids[first[np.argmax(counts > 1)]]
        raise ValueError(f"{name}: two traces have the case id {dup!r}; case ids must be "
                         "unique")


def _from_csv(path, case_id, activity, timestamp, name):
    try:
        frame = read_csv_rows(path, name, dtype={case_id: str, activity: str, timestamp: str})
    except (pd.errors.ParserError, pd.errors.EmptyDataError, UnicodeDecodeError) as exc:
        raise ValueError(f"{name}: {exc}") from None
    except OSError as exc:
        raise ValueError(f"{name}: cannot read ({exc.strerror or exc})") from None
    return _from_frame(frame, case_id, name, first_line=2)


def _from_frame(frame, case_id, name, first_line=None):
    if case_id not in frame.columns:
        raise ValueError(f"{name}: no case id column {case_id!r}; the columns are "
                         f"{list(frame.columns)} (name it with case_id=)")
    if _CASE in frame.columns:
        raise ValueError(f"{name}: the column name {_CASE!r} is reserved")
    if len(frame) == 0:
        raise ValueError(f"{name}: the event log has no events")
    raw = frame[case_id]
    bad = raw.isna().to_numpy()
    if bad.any():
        row = int(np.argmax(bad))
        at = f"line {row + first_line}" if first_line else f"row {row}"
        raise ValueError(f"{name}: {at} has no case id (column {case_id!r})")
    codes, ids = pd.factorize(raw, sort=False)
    events = frame.drop(columns=[case_id]).reset_index(drop=True)
    events.insert(0, _CASE, codes.astype(np.int64))
    ids = np.asarray(ids, dtype=object)

    def case_table(label, events, starts, where):
        found = [c for c in (f"case:{label.removeprefix('case:')}", label)
                 if c in events.columns]
        if not found:
            raise ValueError(f"{name}: no label column {label!r} (nor case:{label}); the "
                             f"columns are {_listed(events)}")
        if len(set(found)) > 1:
            raise ValueError(f"{name}: both {found[0]!r} and {found[1]!r} are columns; name "
                             "the label column exactly (label='case:...')")
        source = events[_EVENT].to_numpy()
        return _case_constant(events[found[0]], starts, found[0], where, source), found[0]

    return events, ids, case_table


# ---------------------------------------------------------------- order
def order_events(events, activity, timestamp, where):
    """Group events by case and order them by timestamp within each case (stable).

    Parameters
    ----------
    events : DataFrame
        ``__case__`` (each event's case position) then the event columns, in source order.
    activity : str
        The activity column; every event needs one.
    timestamp : str or None
        The timestamp column (text is parsed); ``None``: source order.
    where : object
        Names cases and events in messages (``case(i)``, ``event(i, k)``).

    Returns
    -------
    events : DataFrame
        Sorted by case, then time; the timestamp column parsed; ``__event__`` the event's
        position in its case in the source.
    starts : ndarray of shape (n_cases + 1,)
        Case ``i``'s events are rows ``starts[i]:starts[i + 1]``.
    """
    if activity not in events.columns:
        raise ValueError(f"{where.source}: no activity column {activity!r}; the columns are "
                         f"{_listed(events)} (name it with activity=)")
    codes = events[_CASE].to_numpy()
    order = np.argsort(codes, kind="stable")
    if not (np.diff(codes) >= 0).all():
        events = events.iloc[order].reset_index(drop=True)
        codes = codes[order]
    counts = np.bincount(codes)
    starts = np.concatenate([[0], np.cumsum(counts)]).astype(np.int64)
    local = np.arange(len(codes)) - starts[codes]
    events = events.assign(**{_EVENT: local})
    no_act = events[activity].isna().to_numpy()
    if no_act.any():
        e = int(np.argmax(no_act))
        raise ValueError(f"{where.event(codes[e], local[e])} has no activity (column "
                         f"{activity!r})")
    if timestamp is None:
        return events, starts
    times, key = _times(events[timestamp], codes, local, timestamp, where)
    missing = pd.isna(times)
    n_missing = np.bincount(codes, weights=missing, minlength=len(counts))
    partial = np.flatnonzero((n_missing > 0) & (n_missing < counts))
    if len(partial):
        i = partial[0]
        k = int(np.argmax(missing[starts[i]:starts[i + 1]]))
        raise ValueError(f"{where.event(i, k)} has no timestamp (column {timestamp!r}) but "
                         "other events of the case have one; give every event of a case a "
                         "timestamp, or none (source order)")
    events = events.assign(**{timestamp: times})
    key = np.where(missing, 0, key)
    order = np.lexsort((key, codes))
    if (order != np.arange(len(order))).any():
        events = events.iloc[order].reset_index(drop=True)
    return events, starts


def _times(column, codes, local, name, where):
    """The timestamps (datetime or numbers) and an int64 / float sort key."""
    if pd.api.types.is_datetime64_any_dtype(column.dtype):
        times = column
    elif pd.api.types.is_numeric_dtype(column.dtype) and not pd.api.types.is_bool_dtype(
            column.dtype):
        values = column.to_numpy(dtype=np.float64, na_value=np.nan)
        return column, values
    else:
        times = _parse_times(column, codes, local, name, where)
    return times, pd.DatetimeIndex(times).asi8


def _parse_times(column, codes, local, name, where):
    for kwargs in ({"format": "ISO8601"}, {"format": "ISO8601", "utc": True}, {},
                   {"utc": True}):
        try:
            return pd.to_datetime(column, errors="raise", **kwargs)
        except (ValueError, TypeError, OverflowError):
            continue
    parsed = pd.to_datetime(column, errors="coerce", utc=True, format="ISO8601")
    bad = (parsed.isna() & column.notna()).to_numpy()
    e = int(np.argmax(bad))
    raise ValueError(f"{where.event(codes[e], local[e])} has the timestamp "
                     f"{column.iloc[e]!r} (column {name!r}), which is not a date-time")


# ---------------------------------------------------------------- cases
def case_frames(events, starts, activity, timestamp):
    """One DataFrame per case: ``concept:name``, ``time:timestamp``, the event attributes.

    Parameters
    ----------
    events : DataFrame
        Ordered by :func:`order_events`.
    starts : ndarray of shape (n_cases + 1,)
        The cases' first rows.
    activity, timestamp : str or None
        The activity and timestamp columns (renamed to pm4py's names).

    Returns
    -------
    cases : list of DataFrame
    """
    rename = {activity: ACTIVITY}
    if timestamp is not None:
        rename[timestamp] = TIMESTAMP
    keep = [activity, *([timestamp] if timestamp is not None else [])]
    keep += [c for c in events.columns
             if c not in keep and c not in (_CASE, _EVENT) and not str(c).startswith("case:")]
    clash = [c for c in keep[len(rename):] if c in rename.values()]
    if clash:
        raise ValueError(f"the event column {clash[0]!r} would clash with the renamed "
                         f"activity / timestamp column")
    frame = events[keep].rename(columns=rename)
    codes = events[_CASE].to_numpy()
    cases = []
    for _, g in frame.groupby(codes, sort=False):
        g.index = pd.RangeIndex(len(g))  # in place: set_axis would copy every case's blocks
        cases.append(g)
    return cases
