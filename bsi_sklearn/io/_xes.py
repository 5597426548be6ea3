"""XES event logs (IEEE 1849) streamed into columns: a vectorised scanner, else expat.

The scanner (``_xes_scan.py``) reads the file in chunks with numpy and steps aside (for the
whole file) on anything it cannot vouch for; the standard library's expat parser then reads it.

The file is read once, as a stream of start and end tags: no element tree of the document (or
of a trace) is ever built, so a log of millions of events costs its columns, not its XML.
Attributes are read as pm4py reads them: a trace's top-level attributes become ``case:<key>``,
an event's become ``<key>``; typed by their tag (``string``, ``id``, ``date``, ``int``,
``float``, ``boolean``). Nested (meta-)attributes and the values of XES 2.0 ``list`` /
``container`` attributes are not read; ``<global>`` defaults and log-level attributes neither.
"""

from __future__ import annotations

import gzip
import os
import xml.parsers.expat
from dataclasses import dataclass

import numpy as np
import pandas as pd

from bsi_sklearn.io._xes_scan import Unsure, scan_xes

__all__ = ["XesColumns", "read_xes_columns"]

#: Attribute tags whose value is read, and how.
_TYPED = ("string", "id", "date", "int", "float", "boolean")
#: Attribute tags whose children are other attributes (not read).
_NESTING = ("list", "container", "values")
_CHUNK = 1 << 20
_FAST_CHUNK = 8 << 20
_EVENT, _TRACE, _NEST = "event", "trace", "nested"


@dataclass(frozen=True)
class XesColumns:
    """A log's events and traces as columns, in file order.

    Attributes
    ----------
    events : DataFrame
        One row per event: ``__case__`` (the trace's position, from 0) then one column per
        event attribute key (missing values NaN / None / NaT / <NA>).
    traces : dict
        ``key -> list`` of every trace's value of each trace attribute (``None`` when missing),
        already typed.
    n_traces : int
        Number of traces.
    """

    events: pd.DataFrame
    traces: dict
    n_traces: int


def _open(path):
    name = os.fspath(path)
    if name.lower().endswith(".gz"):
        return gzip.open(name, "rb")
    return open(name, "rb")


class _Columns:
    """The values of one attribute key: owners (event or trace positions), values, XES type."""

    __slots__ = ("owners", "values", "kind", "mixed", "add_owner", "add_value")

    def __init__(self, kind):
        self.owners = []
        self.values = []
        self.kind = kind
        self.mixed = False
        self.add_owner = self.owners.append
        self.add_value = self.values.append

    @classmethod
    def of(cls, owners, values, kind, mixed):
        """A column the scanner read: owner positions (array) and values (list)."""
        col = cls(kind)
        col.owners, col.values, col.mixed = owners, values, mixed
        return col


def read_xes_columns(path, case_name="trace", *, fast=True, chunk=None):
    """Stream an XES file (``.xes`` or gzip-compressed ``.xes.gz``) into columns.

    Parameters
    ----------
    path : str or path-like
        The file.
    case_name : str, default="trace"
        What a trace is called in messages.
    fast : bool, default=True
        Read with the vectorised scanner (``_xes_scan.py``) first; a file it cannot vouch
        for is then read with expat, whole. ``False``: expat only.
    chunk : int, default=None
        Bytes read at a time (tests use tiny chunks so that tags cross chunk boundaries).

    Returns
    -------
    columns : XesColumns

    Raises
    ------
    ValueError
        Naming the file and line of malformed XML, the trace of an empty trace, or the trace,
        event and key of a value its type cannot read.
    """
    name = os.fspath(path)
    scanned = None
    if fast:
        try:
            with _open(name) as fh:
                scanned = scan_xes(fh, chunk or _FAST_CHUNK)
        except Unsure:
            scanned = None
        except (OSError, EOFError) as exc:
            raise ValueError(f"{name}: cannot read ({exc})") from None
    if scanned is None:
        event_cols, trace_cols, counts, stray, n_ev, n_tr = _expat_scan(name, chunk or _CHUNK)
    else:
        events, traces, counts, stray, n_ev, n_tr = scanned
        event_cols = {k: _Columns.of(*v) for k, v in events.items()}
        trace_cols = {k: _Columns.of(*v) for k, v in traces.items()}
    if stray:
        raise ValueError(f"{name}: event {stray[0]} (counted over the file, from 0) is not "
                         "directly inside a <trace>")
    traces = {key: _typed(col, n_tr, f"{name}: {case_name} attribute {key!r}",
                          lambda i: f"{case_name} {i}")
              for key, col in trace_cols.items()}
    ids = traces.get("concept:name")

    def trace_of(i):
        if ids is None or pd.isna(ids[i]):
            return f"{case_name} {i} (counted from 0)"
        return f"{case_name} {ids[i]!r}"

    counts = np.asarray(counts, dtype=np.int64)
    if (counts == 0).any():
        i = int(np.argmin(counts))
        raise ValueError(f"{name}: {trace_of(i)} has no events; every case needs at least "
                         f"one ({int((counts == 0).sum())} empty {case_name}(s))")
    owners = np.repeat(np.arange(n_tr, dtype=np.int64), counts)
    starts = np.concatenate([[0], np.cumsum(counts)[:-1]]).astype(np.int64)

    def event_of(i):
        case = int(owners[i])
        return f"{trace_of(case)}, event {i - int(starts[case])}"

    data = {"__case__": owners}
    for key, col in event_cols.items():
        data[key] = _typed(col, n_ev, f"{name}: event attribute {key!r}", event_of)
    return XesColumns(pd.DataFrame(data), traces, n_tr)


def _expat_scan(name, size):
    """The expat reader: (event columns, trace columns, counts, strays, n_ev, n_tr)."""
    event_cols, trace_cols, outside = {}, {}, {}
    tags, counts, stray = {}, [], []
    # The hot path (an attribute of an event) reads only closure variables: the table the
    # current element's attributes go to and the position of their owner.
    table, owner = outside, 0
    depth = n_ev = n_tr = tr_start = 0

    def first(tag, attrs):
        # The root element names the prefix every tag carries (none for <log>).
        prefix = tag[:-3] if tag.endswith("log") else ""
        for t in _TYPED:
            tags[prefix + t] = t
        for t in _NESTING:
            tags[prefix + t] = _NEST
        tags[prefix + "event"] = _EVENT
        tags[prefix + "trace"] = _TRACE
        parser.StartElementHandler = start

    def start(tag, attrs):
        nonlocal depth, table, owner, tr_start
        if depth:  # inside an attribute: a nested (meta-)attribute, not read
            depth += 1
            return
        kind = tags.get(tag)
        if kind is None:
            return
        if kind is _EVENT:
            if table is not trace_cols:
                stray.append(n_ev)
            table, owner = event_cols, n_ev
        elif kind is _TRACE:
            table, owner, tr_start = trace_cols, n_tr, n_ev
        else:
            depth = 1
            if kind is _NEST:
                return
            key = attrs.get("key")
            col = table.get(key)
            if col is None:
                col = table[key] = _Columns(kind)
            elif col.kind is not kind:
                col.mixed = True
            col.add_owner(owner)
            col.add_value(attrs.get("value"))

    def end(tag):
        nonlocal depth, table, owner, n_ev, n_tr
        if depth:
            depth -= 1
            return
        kind = tags.get(tag)
        if kind is _EVENT:
            n_ev += 1
            table, owner = trace_cols, n_tr
        elif kind is _TRACE:
            counts.append(n_ev - tr_start)
            n_tr += 1
            table, owner = outside, 0

    parser = xml.parsers.expat.ParserCreate()
    parser.buffer_text = True
    parser.StartElementHandler = first
    parser.EndElementHandler = end
    try:
        with _open(name) as fh:
            while True:
                chunk = fh.read(size)
                parser.Parse(chunk, not chunk)
                if not chunk:
                    break
    except xml.parsers.expat.ExpatError as exc:
        raise ValueError(f"{name}: not well-formed XES (XML) at line {exc.lineno}, column "
                         f"{exc.offset}: {xml.parsers.expat.errors.messages[exc.code]}"
                         ) from None
    except (OSError, EOFError) as exc:
        raise ValueError(f"{name}: cannot read ({exc})") from None
    return event_cols, trace_cols, counts, stray, n_ev, n_tr


def _first_bad(values, convert):
    for k, v in enumerate(values):
        try:
            convert(v)
        except (TypeError, ValueError):
            return k
    return None  # pragma: no cover - only called after a conversion failed


def _typed(col, n, what, where):
    """One key's values as a column of ``n`` rows, typed by its XES tag."""
    owners = np.asarray(col.owners, dtype=np.int64)
    same = np.flatnonzero(np.diff(owners) == 0)  # owners are appended in file order
    if len(same):
        dup = owners[same[0]]
        raise ValueError(f"{what} is given twice in {where(int(dup))}")
    complete = len(owners) == n
    values = col.values
    tag = "string" if col.mixed else col.kind
    if tag in ("string", "id"):
        out = np.full(n, None, dtype=object)
        out[owners] = values
        return out
    if tag == "date":
        parsed = pd.to_datetime(pd.Series(values, dtype=object), utc=True, format="ISO8601",
                                errors="coerce")
        bad = parsed.isna().to_numpy()
        if bad.any():
            k = int(np.argmax(bad))
            raise ValueError(f"{what}: {where(int(owners[k]))} has the date {values[k]!r}, "
                             "which is not an ISO 8601 date-time")
        dates = pd.DatetimeIndex(parsed)
        if complete:  # owners are increasing: every owner once, in order
            return dates.array
        naive = dates.tz_convert(None).to_numpy()
        full = np.full(n, np.datetime64("NaT"), dtype=naive.dtype)
        full[owners] = naive
        return pd.DatetimeIndex(full).tz_localize("UTC").array
    if tag == "boolean":
        low = np.char.lower(np.asarray(values, dtype=str))
        true = (low == "true") | (low == "1")
        bad = ~(true | (low == "false") | (low == "0"))
        if bad.any():
            k = int(np.argmax(bad))
            raise ValueError(f"{what}: {where(int(owners[k]))} has the boolean "
                             f"{values[k]!r}, which is not true / false")
        if complete:
            out = np.zeros(n, dtype=bool)
            out[owners] = true
            return out
        return _masked(pd.arrays.BooleanArray, np.zeros(n, dtype=bool), owners, true)
    kind = np.int64 if tag == "int" else np.float64
    try:
        typed = np.asarray(values, dtype=object).astype(kind)
    except (TypeError, ValueError, OverflowError):
        k = _first_bad(values, int if tag == "int" else float)
        raise ValueError(f"{what}: {where(int(owners[k]))} has the {tag} {values[k]!r}, "
                         f"which is not a number of that type") from None
    if complete:
        out = np.empty(n, dtype=kind)
        out[owners] = typed
        return out
    if tag == "float":
        out = np.full(n, np.nan)
        out[owners] = typed
        return out
    return _masked(pd.arrays.IntegerArray, np.zeros(n, dtype=np.int64), owners, typed)


def _masked(kind, out, owners, values):
    """A pandas nullable array, missing everywhere but at ``owners``."""
    mask = np.ones(len(out), dtype=bool)
    out[owners] = values
    mask[owners] = False
    return kind(out, mask)
