"""`PosteriorMonitor`: three-valued runtime monitoring of a growing trace under a posterior.

Every candidate clause of the posterior is *open*, *satisfied* or *violated* after steps
``0..t`` of a trace that is still running (the project design, monitoring):

- ``G(p)`` is violated at the first step with ``p`` false, else open;
- ``pi -> F(omega)`` is satisfied at the first step with ``omega`` (or at once when ``pi`` is
  false at step 0), else open;
- ``pi_a -> (!omega_b U omega_a)`` is satisfied at the first ``omega_a`` with no earlier
  ``omega_b`` (or at once when ``pi_a`` is false at step 0), violated at an ``omega_b`` before
  any ``omega_a`` (an ``omega_a`` at the same step satisfies), else open;
- a pattern clause (DESIGN §12) is violated as soon as no continuation of the trace can satisfy
  its template, satisfied as soon as every continuation does, else open: the state of its
  instance of the template's minimal DFA tells
  (:func:`~bsi_sklearn.specification.template_automata.template_dfa`).

A specification is violated when any of its clauses is, satisfied when all are, else open; the
verdict's three probabilities are the posterior masses of those three sets. Closing the trace
(its last state repeats forever) satisfies the open ``G`` clauses and violates the open ``F``
and ``U`` clauses; an open pattern clause is satisfied when its template holds on the finite
trace (its DFA state accepts): ``p_satisfied`` is then the vote, :meth:`Posterior.predict_proba`.

A clause never leaves a decided state, so the monitor keeps one state per clause slot and
recomputes the specifications' states (one AND per word of their clause masks) only at the
steps where a clause changed: a step costs ``O(n_clauses)``, plus ``O(n_specs)`` at the at most
``n_clauses`` steps of a trace where something changed, whatever the trace's length.
The clause states and the masses are numba kernels (``_clause_states.py``).
"""

from __future__ import annotations

import numbers
from collections.abc import Mapping
from typing import NamedTuple

import numpy as np

from bsi_sklearn.data.traces import Traces
from bsi_sklearn.model.clauses import n_clauses
from bsi_sklearn.model.state_layout import join_state
from bsi_sklearn.monitor._clause_states import (
    STATE_NAMES,
    _close,
    _initial_state,
    _masses,
    _monitor_all,
    _pack_states,
    _step,
    pack_patterns,
)
from bsi_sklearn.param_validation import Interval, validate_params
from bsi_sklearn.posterior import Posterior

__all__ = ["ClauseEvent", "PosteriorMonitor", "Verdict", "monitor_traces"]

class ClauseEvent(NamedTuple):
    """A clause of the posterior that changed state at a step.

    Attributes
    ----------
    clause : tuple
        Clause key: ``("G", p)``, ``("F", w)``, ``("U", a, b)`` (*a precedes b*) or
        ``("P", template, propositions)`` (a pattern clause).
    state : str
        ``"satisfied"`` or ``"violated"``.
    inclusion_probability : float
        Posterior mass of the specifications that contain the clause.
    """

    clause: tuple
    state: str
    inclusion_probability: float


class Verdict(NamedTuple):
    """The monitor's verdict after a step.

    Attributes
    ----------
    step : int
        Index of the last step read (``T - 1`` after :meth:`PosteriorMonitor.finish`).
    p_satisfied, p_violated, p_open : float
        Posterior mass of the specifications satisfied, violated and still open; they sum to 1.
    events : tuple of ClauseEvent
        Clauses (of at least one specification of the posterior) that changed state at this
        step, in clause order.
    closed : bool
        Whether the trace was closed by :meth:`PosteriorMonitor.finish`.
    """

    step: int
    p_satisfied: float
    p_violated: float
    p_open: float
    events: tuple
    closed: bool


class PosteriorMonitor:
    """Monitor a running trace under a posterior over specifications.

    Usually obtained from :meth:`BSIClassifier.monitor`. Feed one time step at a time to
    :meth:`update`; each call returns a :class:`Verdict`. :meth:`finish` closes the trace (its
    last state repeats forever) and :meth:`reset` starts a new one.

    Parameters
    ----------
    posterior : Posterior
        The posterior whose specifications are monitored.
    binarize : float, default=None
        When set, step values ``> binarize`` are true; otherwise they must be 0/1 or boolean
        (as for the traces the classifier was fitted on).

    Attributes
    ----------
    names : list
        The propositions a step holds, in order (column names, or column indices).
    n_steps : int
        Steps read since the last :meth:`reset`.
    verdict : Verdict or None
        The last verdict (``None`` before the first step).

    See Also
    --------
    BSIClassifier.monitor_proba : the verdicts over time of whole traces.

    Notes
    -----
    See the module docstring (:mod:`bsi_sklearn.monitor.posterior_monitor`) for the
    three-valued semantics and the cost of a step.

    Examples
    --------
    >>> import numpy as np
    >>> from bsi_sklearn import BSIClassifier
    >>> X = [np.array([[1, 0, 0], [1, 1, 0], [1, 1, 1]]),
    ...      np.array([[1, 0, 0], [1, 0, 0], [1, 1, 0], [1, 1, 1]])]
    >>> clf = BSIClassifier(global_candidates=[0], subtasks=[1, 2], random_state=0).fit(X)
    >>> mon = clf.monitor()
    >>> v = mon.update([1, 0, 0])
    >>> round(v.p_open, 3), v.events
    (1.0, ())
    >>> v = mon.update([1, 1, 0])
    >>> [(e.clause, e.state) for e in v.events]
    [(('F', 1), 'satisfied'), (('U', 1, 2), 'satisfied')]
    >>> v = mon.update({0: True, 1: True, 2: True})  # G(0) stays open until the end
    >>> v = mon.finish()
    >>> v.p_open, v.closed
    (0.0, True)
    >>> trace = np.array([[1, 0, 0], [1, 1, 0], [1, 1, 1]])
    >>> bool(v.p_satisfied == clf.posterior_.predict_proba([trace])[0, 1])
    True
    >>> clf.monitor_proba([trace])[0].shape
    (3, 3)
    """

    def __init__(self, posterior, *, binarize=None):
        validate_params({"posterior": posterior, "binarize": binarize},
                        {"posterior": [Posterior],
                         "binarize": [None, Interval(numbers.Real, None, None, closed="neither")]},
                        "PosteriorMonitor")
        self.posterior = posterior
        self.binarize = binarize
        roles = posterior.roles
        self.names = list(roles.names)
        self._shape = (len(self.names),)
        self._position = {name: i for i, name in enumerate(self.names)}
        self._g_idx, self._s_idx = _global_columns(roles), roles.subtask_idx
        self._c_idx = roles.condition_idx
        self._patterns = pack_patterns(roles.patterns)
        # [n_g, n, g_idx | s_idx | c_idx]: one argument for the step kernel, the columns laid
        # out as a hypothesis' entries are (one per global slot, two per subtask)
        n_g, n = self._g_idx.shape[0], roles.n_subtasks
        self._layout = np.concatenate([[n_g, n],
                                       join_state(self._g_idx, self._s_idx, self._c_idx)])
        self._masks = _checked_masks(posterior, n_g, n)  # (n_specs, n_words) clause masks
        self._probs = np.ascontiguousarray(posterior.probabilities, dtype=np.float64)
        n_slots = n_clauses(n_g, n)
        bits = np.unpackbits(self._masks.view(np.uint8), axis=1, bitorder="little")
        self._used = bits[:, :n_slots].any(axis=0)  # clauses of at least one specification
        # The posterior's own keys and marginals, its pattern clauses' among them.
        slots = posterior._clause_slots()
        self._keys = dict(zip(slots, posterior.clause_keys()))
        self._marginal = dict(zip(slots, posterior.clause_marginals().to_numpy().tolist()))
        self._changed = np.empty(n_slots, dtype=np.int64)
        self._p = np.zeros(3)
        self._words = np.zeros((2, self._masks.shape[1]), dtype=np.uint64)  # open, violated
        self._state0 = _initial_state(n_g, n)
        _pack_states(self._state0, self._words)
        _masses(self._masks, self._probs, self._words, self._p)
        self._floats0 = tuple(self._p.tolist())  # before any step: every clause open
        self.reset()

    def reset(self):
        """Start a new trace: every clause open.

        Returns
        -------
        self : PosteriorMonitor
        """
        self._state = self._state0.copy()
        self._dfa_state = self._patterns.start.copy()
        self._floats = self._floats0
        self.n_steps = 0
        self.verdict = None
        self._closed = False
        return self

    @property
    def closed(self):
        """Whether :meth:`finish` closed the trace."""
        return self._closed

    def update(self, step):
        """Read the next time step and return the verdict on the trace so far.

        Parameters
        ----------
        step : array-like of shape (n_props,), pandas.Series or dict
            The propositions at this step: an array in the order of :attr:`names`, or a Series /
            dict keyed by every proposition name.

        Returns
        -------
        verdict : Verdict

        Raises
        ------
        ValueError
            For a step of the wrong width, a missing or unknown proposition, a value that is
            not 0/1 or boolean (naming the step index and the proposition), or a trace already
            closed by :meth:`finish`.
        """
        if self._closed:
            raise ValueError(
                f"the trace was closed by finish() after {self.n_steps} steps; call reset() "
                "to monitor a new trace"
            )
        if (type(step) is np.ndarray and step.shape == self._shape and self.binarize is None
                and step.dtype.kind in "biuf"):
            row = step  # the fast path: one row of a trace, checked by the kernel
        else:
            row = self._check_step(step)
        t = self.n_steps
        n_changed = _step(row, t, self._state, self._layout, self._changed, self._patterns,
                          self._dfa_state)
        if n_changed == 0:  # nothing changed: the masses stand
            self.n_steps = t + 1
            self.verdict = Verdict(t, *self._floats, (), False)
            return self.verdict
        if n_changed < 0:
            self._raise_bad(row, -n_changed - 1)
        return self._conclude(n_changed, t, closed=False)

    def finish(self):
        """Close the trace: its last state repeats forever, so no specification stays open.

        Open ``G`` clauses become satisfied, open ``F`` and ``U`` clauses violated, an open
        pattern clause satisfied when its template holds on the trace read. Then
        ``p_open == 0`` and ``p_satisfied`` equals ``posterior.predict_proba([trace])[0, 1]``.

        Returns
        -------
        verdict : Verdict
        """
        if self._closed:
            raise ValueError("the trace is already closed; call reset() to start a new one")
        if self.n_steps == 0:
            raise ValueError("finish() needs at least one step; a trace cannot be empty")
        n_changed = _close(self._state, self._g_idx.shape[0], self._changed, self._patterns,
                           self._dfa_state)
        self._closed = True
        return self._conclude(n_changed, self.n_steps - 1, closed=True)

    def clause_states(self):
        """State of every clause of the posterior's specifications.

        Returns
        -------
        pandas.Series
            ``"open"``, ``"satisfied"`` or ``"violated"``, indexed by clause key.
        """
        import pandas as pd
        slots = [s for s in self._keys if self._used[s]]
        return pd.Series([STATE_NAMES[self._state[s]] for s in slots],
                         index=pd.Index([self._keys[s] for s in slots], tupleize_cols=False,
                                        name="clause"), name="state")

    # ------------------------------------------------------------------ internals
    def _conclude(self, n_changed, step, closed):
        events = ()
        if n_changed:
            _pack_states(self._state, self._words)
            _masses(self._masks, self._probs, self._words, self._p)
            self._floats = tuple(self._p.tolist())
            events = tuple(
                ClauseEvent(self._keys[s], STATE_NAMES[self._state[s]], self._marginal[s])
                for s in self._changed[:n_changed].tolist() if self._used[s]
            )
        if not closed:
            self.n_steps += 1
        self.verdict = Verdict(step, *self._floats, events, closed)
        return self.verdict

    def _check_step(self, step):
        """A 1-D numeric array of the step's values (0/1 checked by the kernel)."""
        arr = self._step_array(step)
        if arr.dtype.kind not in "biuf":
            arr = self._numeric(arr)
        if self.binarize is not None:
            if arr.dtype.kind == "f" and not np.isfinite(arr).all():
                self._raise_bad(arr, int(np.argmax(~np.isfinite(arr))))
            return (arr > self.binarize).astype(np.uint8)
        return arr

    def _step_array(self, step):
        t, names = self.n_steps, self.names
        if isinstance(step, Mapping) or (hasattr(step, "index") and hasattr(step, "to_numpy")
                                         and getattr(step, "ndim", 1) == 1):
            keys = list(step.index if hasattr(step, "to_numpy") else step.keys())
            for k in keys:
                if k not in self._position:
                    raise ValueError(
                        f"step {t}: unknown proposition {k!r}; the posterior's propositions "
                        f"are {names}"
                    )
            if len(set(keys)) != len(keys):
                raise ValueError(f"step {t}: a proposition is given more than once")
            missing = [n for n in names if n not in set(keys)]
            if missing:
                raise ValueError(f"step {t}: proposition {missing[0]!r} is missing")
            values = [step[n] for n in names]
            try:
                return np.asarray(values)
            except (TypeError, ValueError):
                return np.asarray(values, dtype=object)
        arr = np.asarray(step)
        if arr.ndim != 1:
            raise ValueError(
                f"step {t} must be a 1-D array of {len(names)} propositions, a Series or a "
                f"dict; got an array of shape {arr.shape}"
            )
        if arr.shape[0] != len(names):
            raise ValueError(
                f"step {t} has {arr.shape[0]} propositions, but the posterior was inferred "
                f"over {len(names)}: {names}"
            )
        return arr

    def _numeric(self, arr):
        for p, v in enumerate(arr.tolist()):
            if isinstance(v, str) or not isinstance(v, (bool, int, float, np.number)):
                raise ValueError(
                    f"step {self.n_steps}: proposition {self.names[p]!r} has the non-numeric "
                    f"value {v!r}"
                )
        return arr.astype(np.float64)

    def _raise_bad(self, arr, p):
        t, name, value = self.n_steps, self.names[p], arr[p].item()
        if not np.isfinite(value):
            raise ValueError(f"step {t}: proposition {name!r} is {value!r}")
        raise ValueError(
            f"step {t}: proposition {name!r} has value {value!r}; steps must be 0/1 or boolean"
            " (or set binarize)"
        )


def monitor_traces(posterior, traces):
    """Verdicts over time of whole traces (the batch form of :class:`PosteriorMonitor`).

    Parameters
    ----------
    posterior : Posterior
    traces : Traces
        Validated traces (:func:`bsi_sklearn.data.traces.check_traces`).

    Returns
    -------
    verdicts : list of ndarray of shape (T_i, 3)
        Row ``t`` of trace ``i`` is ``(p_satisfied, p_violated, p_open)`` after steps ``0..t``
        of a trace still running.
    """
    if not isinstance(traces, Traces):
        raise TypeError("traces must be a Traces object "
                        "(see bsi_sklearn.data.traces.check_traces)")
    roles = posterior.roles
    g_idx = _global_columns(roles)
    masks = _checked_masks(posterior, g_idx.shape[0], roles.n_subtasks)
    out = _monitor_all(traces.data, traces.offsets, g_idx, roles.subtask_idx,
                       roles.condition_idx, masks,
                       np.ascontiguousarray(posterior.probabilities, dtype=np.float64),
                       pack_patterns(roles.patterns))
    return [out[traces.offsets[i]:traces.offsets[i + 1]] for i in range(traces.n_demos)]


def _global_columns(roles):
    """The column of every global slot: the ``G`` candidates', then -1 for each pattern."""
    return np.concatenate([np.asarray(roles.global_idx, dtype=np.int64),
                           np.full(roles.n_patterns, -1, dtype=np.int64)])


def _checked_masks(posterior, n_g, n):
    """The posterior's clause masks, refused when they do not lay out its roles' slots."""
    masks, n_slots = posterior._masks, n_clauses(n_g, n)  # same package: the private masks
    # The marginals have one entry a slot: they tell a layout short of a few slots too.
    if masks.shape[1] != (n_slots + 63) // 64 or (
            posterior.roles.n_patterns and len(posterior._marginals) != n_slots):
        r = posterior.roles
        raise ValueError(f"the posterior's clause masks do not cover the {n_slots} clause slots "
                         f"of its roles ({r.n_globals} G candidates, {r.n_patterns} pattern "
                         f"candidates, {r.n_subtasks} subtasks): its specifications were laid "
                         "out without the pattern candidates")
    return masks
