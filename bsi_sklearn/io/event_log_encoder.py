"""`EventLogEncoder`: cases of events as traces BSI learns from, one proposition per activity."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import pandas as pd
from sklearn.base import BaseEstimator, TransformerMixin
from sklearn.utils.validation import check_is_fitted

from bsi_sklearn.io.event_log import (
    ACTIVITY,
    CASE_ID,
    TIMESTAMP,
    _from_frame,
    _Where,
    order_events,
)
from bsi_sklearn.param_validation import StrOptions, validate_params

__all__ = ["EventLogEncoder"]

_ROWS_PER_BLOCK = 1 << 16


class EventLogEncoder(TransformerMixin, BaseEstimator):
    """Encode cases of events as boolean traces: one proposition per activity.

    A case of ``k`` events becomes a trace of ``k + 1`` steps (a DataFrame whose columns are
    the activity names): step 0 is the case before its first event, step ``t`` the case after
    its ``t``-th event. The traces are what :class:`~bsi_sklearn.BSIClassifier` takes, so its
    specifications read in activity names.

    Parameters
    ----------
    encoding : {"occurred", "current"}, default="occurred"
        ``"occurred"``: column ``a`` at step ``t`` is true when ``a`` occurred among the first
        ``t`` events (false at step 0). ``F(a)`` then reads "a occurs" and ``(!b U a)`` "a
        occurs, and before any b". ``"current"``: column ``a`` at step ``t >= 1`` is true when
        the ``t``-th event is ``a`` (every column false at step 0).
    attributes : dict, default=None
        Extra propositions over event attributes: name -> ``(column, value)`` (true for events
        whose ``column`` equals ``value``) or a callable taking the events of every case as
        one DataFrame (rows in case order, then event order; ``concept:name`` the activity)
        and returning one boolean per event. Encoded like the activities (``"occurred"``:
        some event so far satisfied it; ``"current"``: the current event does). Only for
        cases given as DataFrames.
    handle_unknown : {"error", "ignore"}, default="error"
        An activity seen in ``transform`` but not in ``fit``: a ``ValueError`` naming the case
        and the activity, or (``"ignore"``) the event still makes a step, on which no
        activity column changes.
    repeats : bool, default=False
        Also encode, last, for every activity that occurs at least twice in some case seen in
        fit, the proposition ``a<=1``: ``a`` has occurred at most once so far (``"occurred"``
        only). ``G(a<=1)`` is Declare's ``Absence2(a)``, *a occurs at most once*, a count the
        occurred encoding cannot tell. Like a negated column, ``a<=1`` is true at step 0 and
        never rises, so inferred roles make it a global candidate at most: each repeated
        activity adds one candidate ``G`` clause. ``negations`` leaves it alone: its negation
        ("a occurred twice") rises, a subtask candidate for every repeated activity, and in
        a generated log of 40 activities 35 repeat.
    negations : bool, default=True
        Also encode, after the other propositions, the negation ``!p`` of each of them (the
        activities, then the attributes): true at the steps where ``p`` is false. Under
        ``"occurred"`` ``!a`` reads "a has not occurred yet" and ``G(!a)`` is Declare's
        ``Absence(a)``, *a never occurs*, a clause the template cannot state on the
        activities alone. A negated column is true at step 0 and never rises, so inferred
        roles make it a global candidate at most (never a subtask or a condition): the
        ``n`` extra columns add ``n`` candidate ``G`` clauses, not orders. The default was
        chosen by measurement on the generated logs (``docs/event-log-benchmark.md``);
        ``False`` gives the activities (and attributes) alone.
    case_id, activity, timestamp : str, default pm4py's names
        The columns of a single event DataFrame passed as ``X`` (``case:concept:name``,
        ``concept:name``, ``time:timestamp``); ``activity`` is also the activity column of
        cases given as DataFrames (:func:`~bsi_sklearn.io.read_event_log` names it
        ``concept:name``).

    Attributes
    ----------
    activities_ : ndarray of str
        The activities seen in fit, sorted: the first propositions.
    feature_names_out_ : ndarray of str
        The propositions: the activities, then the names of ``attributes``, then (with
        ``negations=True``) the same names prefixed with ``!``, then (with ``repeats=True``)
        the ``a<=1`` of the repeated activities.
    repeated_ : ndarray of str
        The activities seen twice in some case in fit, whose ``a<=1`` is encoded (empty with
        ``repeats=False``).
    repeats_ : dict
        Each ``a<=1`` column -> its activity: the ``repeats`` argument of
        :func:`bsi_sklearn.report.wording.describe_event_log_specification`.
    negations_ : dict
        Each negated proposition -> the proposition it negates (``{"!pay": "pay", ...}``,
        empty with ``negations=False``): the ``negations`` argument of
        :meth:`Specification.readable` and the sentences of
        :func:`bsi_sklearn.report.wording.describe_event_log_specification`.

    See Also
    --------
    bsi_sklearn.io.read_event_log : Reads the cases (XES, CSV, event DataFrames).
    bsi_sklearn.BSIClassifier : Learns a specification from the traces.

    Notes
    -----
    ``X`` is a list of cases, one of: the DataFrames :func:`~bsi_sklearn.io.read_event_log`
    returns (events in order, an ``activity`` column); sequences of activity names (lists,
    tuples or 1-D arrays; a 2-D array is a list of equal-length sequences); or one event
    DataFrame with a ``case_id`` column (cases in order of first appearance, events ordered
    by ``timestamp`` as the reader orders them). Activity names become column names as
    ``str(name)``. An empty case, or an event without an activity, is a ``ValueError``
    naming the case.

    Examples
    --------
    >>> from bsi_sklearn.io import EventLogEncoder
    >>> enc = EventLogEncoder().fit([["order", "pay", "ship"], ["order", "ship"]])
    >>> enc.get_feature_names_out().tolist()
    ['order', 'pay', 'ship', '!order', '!pay', '!ship']
    >>> enc.transform([["order", "ship"]])[0].astype(int)
       order  pay  ship  !order  !pay  !ship
    0      0    0     0       1     1      1
    1      1    0     0       0     1      1
    2      1    0     1       0     1      0
    """

    _parameter_constraints = {
        "encoding": [StrOptions(("occurred", "current"))],
        "attributes": [None, Mapping],
        "handle_unknown": [StrOptions(("error", "ignore"))],
        "repeats": ["boolean"],
        "negations": ["boolean"],
        "case_id": [str],
        "activity": [str],
        "timestamp": [str, None],
    }

    def __init__(self, *, encoding="occurred", attributes=None, handle_unknown="error",
                 repeats=False, negations=True, case_id=CASE_ID, activity=ACTIVITY,
                 timestamp=TIMESTAMP):
        self.encoding = encoding
        self.attributes = attributes
        self.handle_unknown = handle_unknown
        self.repeats = repeats
        self.negations = negations
        self.case_id = case_id
        self.activity = activity
        self.timestamp = timestamp

    def __sklearn_tags__(self):
        tags = super().__sklearn_tags__()
        tags.input_tags.two_d_array = False
        tags.input_tags.string = True
        tags.transformer_tags.preserves_dtype = []
        return tags

    def _check_attributes(self):
        attrs = dict(self.attributes or {})
        for name, rule in attrs.items():
            pair = isinstance(rule, tuple) and len(rule) == 2
            if not isinstance(name, str) or not (pair or callable(rule)):
                raise ValueError(f"EventLogEncoder: attributes[{name!r}] must be a pair "
                                 f"(column, value) or a callable under a string name, got "
                                 f"{rule!r}")
        return attrs

    def fit(self, X, y=None):
        """Learn the activities (the propositions) from the cases.

        Parameters
        ----------
        X : list of cases or event DataFrame
            See Notes.
        y : None
            Ignored.

        Returns
        -------
        self : EventLogEncoder
        """
        self._fit(self._events(X))
        return self

    def fit_transform(self, X, y=None):
        """Fit on the cases and encode them (reads ``X`` once).

        Parameters
        ----------
        X : list of cases or event DataFrame
            See Notes.
        y : None
            Ignored.

        Returns
        -------
        traces : list of DataFrame
        """
        events = self._events(X)
        self._fit(events)
        return self._encode(events)

    def transform(self, X):
        """Encode cases as traces of ``k + 1`` steps over ``feature_names_out_``.

        Parameters
        ----------
        X : list of cases or event DataFrame
            See Notes.

        Returns
        -------
        traces : list of DataFrame
            One per case, columns ``feature_names_out_``, boolean.
        """
        check_is_fitted(self, "activities_")
        return self._encode(self._events(X))

    def get_feature_names_out(self, input_features=None):
        """The propositions: the activities seen in fit, the attribute names, their negations.

        Parameters
        ----------
        input_features : None
            Ignored (the inputs are cases, not columns).

        Returns
        -------
        names : ndarray of str
        """
        check_is_fitted(self, "activities_")
        return self.feature_names_out_.copy()

    # ------------------------------------------------------------ internals
    def _fit(self, events):
        names = events.names
        attrs = self._check_attributes()
        if attrs and events.frame is None:
            raise ValueError(f"EventLogEncoder: attributes[{next(iter(attrs))!r}] needs the "
                             "cases as DataFrames of events, not sequences of activity names")
        clash = sorted(set(attrs) & set(names))
        if clash:
            raise ValueError(f"EventLogEncoder: the attribute proposition {clash[0]!r} has "
                             "the name of an activity")
        if self.repeats and self.encoding != "occurred":
            raise ValueError("EventLogEncoder: repeats=True needs encoding='occurred' (a<=1 "
                             "is 'a occurred at most once so far'), got "
                             f"encoding={self.encoding!r}")
        self.activities_ = np.array(sorted(set(names)), dtype=object)
        if self.repeats:
            index = np.array([int(np.searchsorted(self.activities_, n)) for n in names],
                             dtype=np.int64)
            case = np.repeat(np.arange(len(events.offsets) - 1), np.diff(events.offsets))
            again = _second_occurrences(case, events.codes, len(names))
            twice = np.unique(index[events.codes][again])
            self.repeated_ = self.activities_[twice]
        else:
            self.repeated_ = np.array([], dtype=object)
        positive = [*map(str, self.activities_), *attrs]
        negated = ["!" + p for p in positive] if self.negations else []
        clash = sorted(set(negated) & set(positive))
        if clash:
            raise ValueError(f"EventLogEncoder: negations=True names the negation of "
                             f"{clash[0][1:]!r} {clash[0]!r}, which is already a proposition "
                             "(an activity or attribute of that name)")
        repeat_names = [f"{a}<=1" for a in map(str, self.repeated_)]
        clash = sorted(set(repeat_names) & {*positive, *negated})
        if clash:
            raise ValueError(f"EventLogEncoder: repeats=True names {clash[0]!r} the "
                             f"repetition of {clash[0][:-3]!r}, which is already a "
                             "proposition (an activity or attribute of that name)")
        self.feature_names_out_ = np.array([*positive, *negated, *repeat_names],
                                           dtype=object)
        self.repeats_ = dict(zip(repeat_names, map(str, self.repeated_)))
        self.negations_ = dict(zip(negated, positive))

    def _events(self, X):
        validate_params(self.get_params(deep=False), self._parameter_constraints,
                        type(self).__name__)
        return _Events.read(X, self)

    def _encode(self, events):
        index = {a: k for k, a in enumerate(self.activities_)}
        lookup = np.array([index.get(n, -1) for n in events.names], dtype=np.int64)
        codes = lookup[events.codes] if len(lookup) else events.codes
        unknown = np.flatnonzero(codes < 0)
        if len(unknown) and self.handle_unknown == "error":
            e = unknown[0]
            i = int(np.searchsorted(events.offsets, e, side="right") - 1)
            raise ValueError(f"EventLogEncoder: {events.case(i)}, event "
                             f"{e - events.offsets[i]} has the activity "
                             f"{events.names[events.codes[e]]!r}, unseen in fit "
                             f"(handle_unknown='ignore' encodes it as no activity)")
        n_act = len(self.activities_)
        columns = [codes >= 0]
        values = [np.where(codes >= 0, codes, 0)]
        for k, (name, rule) in enumerate(self._check_attributes().items()):
            columns.append(_attribute(events, name, rule))
            values.append(np.full(len(codes), n_act + k))
        hits = np.concatenate(columns)
        props = np.concatenate(values)[hits]
        event = np.tile(np.arange(len(codes)), len(columns))[hits]
        n_cases = len(events.offsets) - 1
        case = np.repeat(np.arange(n_cases), np.diff(events.offsets))
        n_pos, n_rep = n_act + len(columns) - 1, len(self.repeated_)
        n_cols = len(self.feature_names_out_)  # the propositions, their negations, the a<=1
        if n_rep:
            # "a occurred twice" rises at a's second event in the case, in a<=1's column.
            slot = np.full(n_act + 1, -1, dtype=np.int64)
            slot[np.searchsorted(self.activities_, self.repeated_)] = np.arange(n_rep)
            second = np.flatnonzero(_second_occurrences(case, codes, len(events.names)))
            second = second[slot[codes[second]] >= 0]
            props = np.concatenate([props, n_cols - n_rep + slot[codes[second]]])
            event = np.concatenate([event, second])
        rows = event + case[event] + 1
        n_rows = len(codes) + n_cases
        data = np.zeros((n_rows, n_cols), dtype=bool)
        data[rows, props] = True
        row_starts = events.offsets + np.arange(n_cases + 1)
        if self.encoding == "occurred":
            _accumulate(data[:, :n_pos], row_starts)
        if self.negations:
            np.logical_not(data[:, :n_pos], out=data[:, n_pos:2 * n_pos])
        if n_rep:  # "occurred twice so far", then its complement, a<=1
            _accumulate(data[:, n_cols - n_rep:], row_starts)
            np.logical_not(data[:, n_cols - n_rep:], out=data[:, n_cols - n_rep:])
        names = pd.Index(self.feature_names_out_.astype(str), dtype=object)
        return [pd.DataFrame(data[a:b], columns=names, copy=False)
                for a, b in zip(row_starts[:-1], row_starts[1:])]


def _second_occurrences(case, codes, n_codes):
    """Whether each event is the second or a later one of its code (activity) in its case.

    ``case`` and ``codes`` give each event's case and code, ``n_codes`` bounds the codes; a
    negative code (an activity unseen in fit) is never a repetition.
    """
    key = case.astype(np.int64) * (n_codes + 1) + np.where(codes >= 0, codes, n_codes)
    order = np.argsort(key, kind="stable")
    sorted_key = key[order]
    later = np.zeros(len(codes), dtype=bool)
    later[order[1:]] = sorted_key[1:] == sorted_key[:-1]
    return later & (codes >= 0)


def _accumulate(data, row_starts):
    """Within each case, a column stays true once it has been (in place, in blocks)."""
    n_cases = len(row_starts) - 1
    first = 0
    while first < n_cases:
        last = int(np.searchsorted(row_starts, row_starts[first] + _ROWS_PER_BLOCK,
                                   side="right")) - 1
        last = min(max(last, first + 1), n_cases)
        a, b = row_starts[first], row_starts[last]
        case = np.repeat(np.arange(1, last - first + 1, dtype=np.int32),
                         np.diff(row_starts[first:last + 1]))
        block = np.where(data[a:b], case[:, None], 0).astype(np.int32)
        np.maximum.accumulate(block, axis=0, out=block)
        data[a:b] = block == case[:, None]
        first = last


def _attribute(events, name, rule):
    """One boolean per event: the events satisfying an attribute rule."""
    if events.frame is None:
        raise ValueError(f"EventLogEncoder: attributes[{name!r}] needs the cases as "
                         "DataFrames of events, not sequences of activity names")
    frame = events.frame
    if callable(rule):
        out = np.asarray(rule(frame))
        if out.shape != (len(frame),):
            raise ValueError(f"EventLogEncoder: attributes[{name!r}] returned shape "
                             f"{out.shape}; it must return one boolean per event "
                             f"({len(frame)})")
        if out.dtype != bool:
            raise ValueError(f"EventLogEncoder: attributes[{name!r}] returned {out.dtype} "
                             "values; it must return booleans")
        return out
    column, value = rule
    if column not in frame.columns:
        raise ValueError(f"EventLogEncoder: attributes[{name!r}] names the column "
                         f"{column!r}, which the events lack (columns: "
                         f"{list(frame.columns)})")
    return (frame[column] == value).fillna(False).to_numpy(dtype=bool)


class _Events:
    """Every case's activities as codes into ``names``, flat, with the cases' offsets."""

    def __init__(self, codes, names, offsets, frame, ids):
        self.codes = codes
        self.names = names
        self.offsets = offsets
        self.frame = frame
        self.ids = ids

    def case(self, i):
        return f"case {i}" if self.ids is None else f"case {self.ids[i]!r}"

    @classmethod
    def read(cls, X, enc):
        if hasattr(X, "columns"):
            return cls._from_event_frame(X, enc)
        if isinstance(X, np.ndarray) and X.ndim == 2:
            X = list(X)
        if not isinstance(X, (list, tuple, np.ndarray)) or isinstance(X, str):
            raise ValueError("EventLogEncoder: X must be a list of cases (DataFrames of "
                             "events or sequences of activity names) or one event DataFrame "
                             f"with a {enc.case_id!r} column, got {type(X).__name__}")
        if len(X) == 0:
            raise ValueError("EventLogEncoder: X has no cases")
        frames = all(hasattr(c, "columns") for c in X)
        if frames:
            missing = [i for i, c in enumerate(X) if enc.activity not in c.columns]
            if missing:
                raise ValueError(f"EventLogEncoder: case {missing[0]} has no activity column "
                                 f"{enc.activity!r} (columns: {list(X[missing[0]].columns)})")
            parts = [c[enc.activity].to_numpy(dtype=object) for c in X]
        else:
            parts = []
            for i, c in enumerate(X):
                if hasattr(c, "columns") or isinstance(c, (str, bytes, Mapping)) or \
                        np.ndim(c) != 1:
                    raise ValueError(f"EventLogEncoder: case {i} is a "
                                     f"{type(c).__name__}; a case is a DataFrame of events "
                                     "or a sequence of activity names (all cases alike)")
                parts.append(np.asarray(c, dtype=object))
        lengths = np.array([len(p) for p in parts], dtype=np.int64)
        offsets = np.concatenate([[0], np.cumsum(lengths)]).astype(np.int64)
        frame = None
        if frames and enc.attributes:
            frame = pd.concat(X, ignore_index=True)
        return cls._coded(np.concatenate(parts), offsets, frame, None)

    @classmethod
    def _from_event_frame(cls, X, enc):
        events, ids, _ = _from_frame(X, enc.case_id, "X")
        where = _Where(ids, "X")
        timestamp = enc.timestamp if enc.timestamp in events.columns else None
        events, starts = order_events(events, enc.activity, timestamp, where)
        frame = events.drop(columns=["__case__", "__event__"])
        frame = frame.rename(columns={enc.activity: ACTIVITY})
        return cls._coded(events[enc.activity].to_numpy(dtype=object), starts,
                          frame if enc.attributes else None, ids)

    @classmethod
    def _coded(cls, flat, offsets, frame, ids):
        events = cls(None, None, offsets, frame, ids)
        empty = np.flatnonzero(np.diff(offsets) == 0)
        if len(empty):
            raise ValueError(f"EventLogEncoder: {events.case(empty[0])} has no events; "
                             "every case needs at least one")
        codes, uniques = pd.factorize(flat, sort=False, use_na_sentinel=True)
        if (codes < 0).any():
            e = int(np.argmax(codes < 0))
            i = int(np.searchsorted(offsets, e, side="right") - 1)
            raise ValueError(f"EventLogEncoder: {events.case(i)}, event {e - offsets[i]} "
                             "has no activity")
        names = [str(u) for u in uniques]
        if len(set(names)) != len(names):
            dup = next(n for n in names if names.count(n) > 1)
            raise ValueError(f"EventLogEncoder: two different activity values read as "
                             f"{dup!r}; activity names are their str()")
        events.codes = codes.astype(np.int64)
        events.names = names
        return events
