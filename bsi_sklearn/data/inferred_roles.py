"""Proposition roles read from the training demonstrations (``BSIClassifier(roles="infer")``).

The rule keeps, for each role, the propositions whose clauses the demonstrations can test,
and looks for each subtask's condition among the propositions' initial values. It reads the
demonstrations once (four boolean statistics per demonstration and proposition) and is
deterministic: the same data give the same roles. The rule and its reasons are written in
``docs/roles.md``.
"""

import warnings
from collections.abc import Mapping

import numpy as np

from bsi_sklearn.data.roles import resolve_propositions, resolve_roles

__all__ = ["infer_roles", "proposition_statistics", "infer_condition", "warn_all_roles"]


def proposition_statistics(traces):
    """What the role rule reads of every demonstration and proposition.

    Parameters
    ----------
    traces : Traces
        The demonstrations (see :func:`bsi_sklearn.data.traces.check_traces`).

    Returns
    -------
    initial : ndarray of shape (n_demos, n_props), dtype bool
        The proposition's value at the first step.
    ever : ndarray of shape (n_demos, n_props), dtype bool
        True at some step (``F p`` holds).
    always : ndarray of shape (n_demos, n_props), dtype bool
        True at every step (``G p`` holds).

    Examples
    --------
    >>> import numpy as np
    >>> from bsi_sklearn.data.traces import check_traces
    >>> traces = check_traces([np.array([[1, 0], [1, 1]]), np.array([[0, 1]])])
    >>> initial, ever, always = proposition_statistics(traces)
    >>> initial.astype(int).tolist(), ever.astype(int).tolist(), always.astype(int).tolist()
    ([[1, 0], [0, 1]], [[1, 1], [0, 1]], [[1, 0], [0, 1]])
    """
    starts = traces.offsets[:-1]
    data = traces.data.astype(bool)
    initial = data[starts]
    ever = np.logical_or.reduceat(data, starts, axis=0)
    always = np.logical_and.reduceat(data, starts, axis=0)
    return initial, ever, always


def infer_condition(initial, done, subtask):
    """The condition of one subtask: the initial value that best separates its completion.

    Over the acceptable demonstrations, a proposition ``c`` (not the subtask itself) is
    eligible when most demonstrations where ``c`` holds at the first step complete the
    subtask and most where it does not hold skip it; among the eligible, the one whose
    initial value agrees with completion on the most demonstrations wins, ties going to the
    fewest demonstrations the clause ``c -> F(subtask)`` would violate, then to the first
    column. When every acceptable demonstration completes the subtask there is nothing to
    explain and the condition is ``true``.

    Parameters
    ----------
    initial : ndarray of shape (n_acceptable, n_props), dtype bool
        Each proposition's value at the first step of every acceptable demonstration.
    done : ndarray of shape (n_acceptable,), dtype bool
        Whether each acceptable demonstration completes the subtask (``F subtask`` holds).
    subtask : int
        The subtask's column.

    Returns
    -------
    condition : int or None
        The condition's column, or None for ``true`` (no condition).

    Examples
    --------
    >>> import numpy as np
    >>> initial = np.array([[1, 0, 1], [1, 0, 0], [0, 0, 1], [1, 0, 0]], dtype=bool)
    >>> done = np.array([True, True, False, True])
    >>> infer_condition(initial, done, subtask=1)   # column 0 holds exactly when done
    0
    >>> print(infer_condition(initial, np.ones(4, dtype=bool), subtask=1))
    None
    """
    done = np.asarray(done, dtype=bool)
    if done.all():
        return None
    c0 = np.asarray(initial, dtype=bool)
    n11 = (c0 & done[:, None]).sum(0)
    n10 = (c0 & ~done[:, None]).sum(0)
    n01 = (~c0 & done[:, None]).sum(0)
    n00 = (~c0 & ~done[:, None]).sum(0)
    eligible = (n11 > n10) & (n00 > n01)
    eligible[subtask] = False
    if not eligible.any():
        return None
    columns = np.flatnonzero(eligible)
    # lexsort: the last key is the primary one (most agreement, then fewest violations,
    # then the first column).
    order = np.lexsort((columns, n10[columns], -(n11 + n00)[columns]))
    return int(columns[order[0]])


def infer_roles(traces, y, global_candidates=None, subtasks=None, conditions=None):
    """Roles from the demonstrations, for every role the user did not give.

    Each of ``global_candidates``, ``subtasks`` and ``conditions`` that is not ``None`` is
    the user's and is used as given (validated as :func:`bsi_sklearn.data.roles.resolve_roles`
    does); each that is ``None`` is inferred:

    - a **global candidate** is a proposition true at every step of at least one acceptable
      demonstration: ``G p`` can hold on the acceptable ones. One that every demonstration
      keeps stays a candidate (its clause is untested, but it is independent of every other
      part of the hypothesis, so the prior and the likelihood decide it);
    - a **subtask** is a proposition that is false at the first step and true at a later one
      in at least one demonstration: it can be completed. One true from the first step of
      every demonstration makes ``F p`` hold before anything is done, and one that never
      changes within a demonstration is a state, not a completion;
    - each subtask's **condition** is found by :func:`infer_condition` among the initial
      values of the other propositions, on the acceptable demonstrations.

    A subtask named in an explicit ``conditions`` mapping is a subtask: it joins the
    inferred subtasks when ``subtasks`` is ``None``. An explicit ``conditions`` is the whole
    role: subtasks without an entry have no condition (``{}``: no conditions at all).

    Parameters
    ----------
    traces : Traces
        The training demonstrations.
    y : ndarray of shape (n_demos,)
        1 for acceptable, 0 for unacceptable demonstrations.
    global_candidates, subtasks : list of str or int, or None
        The user's roles, or ``None`` to infer them.
    conditions : mapping or None
        The user's conditions, or ``None`` to infer them.

    Returns
    -------
    roles : Roles

    Examples
    --------
    >>> import numpy as np
    >>> from bsi_sklearn.data.traces import check_traces
    >>> # columns: safe (true throughout), closed (at the start), opened, done
    >>> X = [np.array([[1, 1, 0, 0], [1, 1, 1, 0], [1, 1, 1, 1]]),
    ...      np.array([[1, 0, 0, 0], [1, 0, 0, 1]]),
    ...      np.array([[1, 1, 0, 0], [1, 1, 0, 1]]),     # skips opening: unacceptable
    ...      np.array([[1, 0, 0, 0], [0, 0, 0, 1]])]     # unsafe: unacceptable
    >>> roles = infer_roles(check_traces(X), np.array([1, 1, 0, 0]))
    >>> roles.global_idx.tolist(), roles.subtask_idx.tolist(), roles.condition_names()
    ([0, 1], [2, 3], {2: 1})
    """
    names = (list(traces.feature_names) if traces.feature_names is not None
             else list(range(traces.n_props)))
    y = np.asarray(y)
    acceptable = y == 1
    initial, ever, always = proposition_statistics(traces)
    if global_candidates is None:
        global_candidates = np.flatnonzero(always[acceptable].any(0)).tolist()
    if subtasks is None:
        rises = (~initial & ever).any(0)
        if isinstance(conditions, Mapping):
            rises[resolve_propositions(list(conditions), names, "conditions")] = True
        subtasks = np.flatnonzero(rises).tolist()
    if conditions is None:
        conditions = {}
        for s in resolve_propositions(subtasks, names, "subtasks").tolist():
            c = infer_condition(initial[acceptable], ever[acceptable, s], s)
            if c is not None:
                conditions[s] = c
    return resolve_roles(global_candidates, subtasks, conditions, traces.n_props,
                         traces.feature_names)


def warn_all_roles(n_props, n_hyp, above_cap, stacklevel=2):
    """Say that, with every proposition in every role, exact enumeration was out of reach.

    Called by :func:`bsi_sklearn.inference.policy.infer` (its ``stacklevel`` points at the
    user's ``fit``). The
    message does not depend on the data beyond its size, so Python's default warning filter
    shows it once per process and problem size, not once per fold.

    Parameters
    ----------
    n_props : int
        Number of propositions.
    n_hyp : str
        Size of the prior's support, written (``priors.format_count``: it may pass a
        float's range).
    above_cap : bool
        Whether the support is above ``max_exact_hypotheses`` (else the work budget was).
    stacklevel : int, default=2
        As :func:`warnings.warn`'s, counted from the caller of this function.
    """
    reason = ("is above max_exact_hypotheses" if above_cap
              else "needs more than inference='auto''s work budget to enumerate exactly "
                   "(about a second, or what sampling would cost, within a cap)")
    warnings.warn(
        f"With roles='all' all {n_props} propositions are global candidates and "
        f"subtasks: the support ({n_hyp} hypotheses) {reason}, so MCMC samples "
        "it. "
        "Say which propositions play which role with global_candidates=, subtasks= and "
        "conditions= (a dataset's Bunch has them: BSIClassifier(**data.roles)), or infer "
        "them from the data with roles='infer' (the default), to make the posterior smaller "
        "and exact.",
        UserWarning,
        stacklevel=stacklevel + 1,
    )
