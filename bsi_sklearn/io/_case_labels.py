"""The labels of an event log's cases, as 0/1, every error naming the case or the event.

A label comes from a case attribute (a column constant within each case: :func:`_case_constant`)
or from a table given apart (a Series or mapping case id -> label, or a two-column CSV file:
:func:`_table_labels`); :func:`_binary` turns the cases' labels into 0/1 (``pos_label`` names
the positive one). ``where`` is ``event_log.py``'s ``_Where``: it names the source, the cases and
the events in messages.
"""

from __future__ import annotations

import os
from numbers import Integral

import numpy as np
import pandas as pd

from bsi_sklearn.io._csv_rows import read_csv_rows


def _case_constant(column, starts, col, where, source):
    """One value per case from a column constant within each case (events grouped by case)."""
    values = column.to_numpy(dtype=object)
    codes, _ = pd.factorize(column, sort=False, use_na_sentinel=True)
    first = codes[starts[:-1]]
    case = np.repeat(np.arange(len(starts) - 1), np.diff(starts))
    k = np.flatnonzero(codes != first[case])
    missing = np.flatnonzero(codes < 0)
    if len(missing) and (not len(k) or missing[0] <= k[0]):
        e = missing[0]
        raise ValueError(f"{where.event(case[e], source[e])} has no label (column {col!r})")
    if len(k):
        e = k[0]
        i = case[e]
        raise ValueError(f"{where.event(i, source[e])} has the label {values[e]!r} in column "
                         f"{col!r}, but event {source[starts[i]]} of the case has "
                         f"{values[starts[i]]!r}: a label is constant within a case")
    return values[starts[:-1]]


def _table_labels(labels, ids, case_id, where):
    if isinstance(labels, (str, os.PathLike)):
        labels = _read_label_file(labels, case_id)
    if isinstance(labels, pd.DataFrame):
        raise ValueError("labels must be a Series indexed by case id, a mapping or a CSV "
                         "file, not a DataFrame (pass frame.set_index(id)[label])")
    if not isinstance(labels, pd.Series):
        try:
            labels = pd.Series(dict(labels), dtype=object)
        except (TypeError, ValueError):
            raise ValueError("labels must be a Series indexed by case id, a mapping case id "
                             f"-> label or a CSV file, got {type(labels).__name__}") from None
    if labels.index.has_duplicates:
        dup = labels.index[labels.index.duplicated()][0]
        raise ValueError(f"labels: the case id {dup!r} has more than one label")
    extra = labels.index.difference(pd.Index(ids, dtype=object))
    missing = pd.Index(ids, dtype=object).difference(labels.index)
    if len(missing):
        i = int(np.flatnonzero(pd.Index(ids, dtype=object).isin(missing))[0])
        raise ValueError(f"{where.case(i)} has no label in the labels table "
                         f"({len(missing)} case(s) without one)")
    if len(extra):
        raise ValueError(f"labels: the case id(s) {list(extra[:5])} are not cases of "
                         f"{where.source}")
    return labels.reindex(pd.Index(ids, dtype=object)).to_numpy(dtype=object)


def _read_label_file(path, case_id):
    name = os.fspath(path)
    try:
        frame = read_csv_rows(path, f"labels {name}", dtype={case_id: str})
    except (pd.errors.ParserError, pd.errors.EmptyDataError, OSError) as exc:
        raise ValueError(f"labels {name}: {exc}") from None
    id_col = case_id if case_id in frame.columns else frame.columns[0]
    others = [c for c in frame.columns if c != id_col]
    if len(others) != 1:
        raise ValueError(f"labels {name}: expected two columns, the case id and the label, "
                         f"got {list(frame.columns)}")
    ids = frame[id_col].astype(str) if frame[id_col].dtype != object else frame[id_col]
    return pd.Series(frame[others[0]].to_numpy(dtype=object), index=ids)


def _binary(values, pos_label, where):
    """Labels (one per case) as 0/1, or a ValueError naming the case."""
    missing = pd.isna(values)
    if missing.any():
        raise ValueError(f"{where.case(np.argmax(missing))} has no label")
    uniq = list(pd.unique(pd.Series(values, dtype=object)))
    if pos_label is None:
        for i, v in enumerate(values):
            if not (isinstance(v, (bool, np.bool_, Integral, float)) and v in (0, 1)):
                raise ValueError(f"{where.case(i)} has the label {v!r}; labels must be 0/1 "
                                 "or True/False, or name the acceptable one with pos_label")
        return (values == 1).astype(np.int64)
    if len(uniq) > 2:
        i = int(np.flatnonzero(~pd.Series(values).isin(uniq[:2]).to_numpy())[0])
        raise ValueError(f"{where.case(i)} has a third label value {values[i]!r} (others: "
                         f"{uniq[:2]!r}); labels must take two values")
    pos = [u for u in uniq if type(u) is type(pos_label) and u == pos_label]
    if not pos and isinstance(pos_label, str):
        pos = [u for u in uniq if str(u) == pos_label
               or isinstance(u, (bool, np.bool_)) and str(u).lower() == pos_label.lower()]
    if not pos:
        pos = [u for u in uniq if u == pos_label]
    if not pos:
        raise ValueError(f"pos_label={pos_label!r} is not among the labels {uniq!r} of "
                         f"{where.source}")
    return np.array([v == pos[0] for v in values], dtype=np.int64)
