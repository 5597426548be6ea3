"""Proposition roles: which columns are global candidates, subtasks and their conditions."""

from __future__ import annotations

import numbers
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

__all__ = ["Roles", "resolve_roles", "resolve_propositions"]


@dataclass(frozen=True)
class Roles:
    """Proposition roles resolved to column indices.

    Attributes
    ----------
    global_idx : ndarray of int64
        Column of every global candidate (the set T).
    subtask_idx : ndarray of int64
        Column of every subtask proposition omega_w (the set Omega).
    condition_idx : ndarray of int64
        Column of each subtask's condition pi_w, or -1 when pi_w = true.
    names : list
        Identifier of every column, as used in specifications.
    patterns : tuple of (str, tuple of int)
        Every pattern-clause candidate (DESIGN §12): its template's name and the column of
        each slot; candidate ``k`` is global slot ``n_globals + k``. Empty by default.
    """

    global_idx: np.ndarray
    subtask_idx: np.ndarray
    condition_idx: np.ndarray
    names: list
    patterns: tuple = ()

    @property
    def n_globals(self):
        """``|T|``."""
        return len(self.global_idx)

    @property
    def n_patterns(self):
        """Number of pattern-clause candidates (global slots after the ``G`` candidates)."""
        return len(self.patterns)

    @property
    def n_subtasks(self):
        """``|Omega|``."""
        return len(self.subtask_idx)

    def global_names(self):
        """Identifiers of the global candidates."""
        return [self.names[i] for i in self.global_idx]

    def pattern_keys(self):
        """``(template name, proposition identifiers)`` of every pattern candidate, in order."""
        return [(name, tuple(self.names[c] for c in cols)) for name, cols in self.patterns]

    def subtask_names(self):
        """Identifiers of the subtasks."""
        return [self.names[i] for i in self.subtask_idx]

    def condition_names(self):
        """Subtask identifier -> condition identifier (only subtasks with a condition)."""
        return {
            self.names[s]: self.names[c]
            for s, c in zip(self.subtask_idx, self.condition_idx)
            if c >= 0
        }

    def to_params(self):
        """The roles as the estimator's parameters: ``BSIClassifier(**roles.to_params())``.

        Returns
        -------
        params : dict
            ``global_candidates`` and ``subtasks`` (lists) and ``conditions`` (subtask ->
            condition, only subtasks with one), by proposition name where the columns have
            names and by column index otherwise, as plain ``str`` / ``int``.

        Examples
        --------
        >>> resolve_roles(None, [1, 2], {2: 0}, 3).to_params()
        {'global_candidates': [0, 1, 2], 'subtasks': [1, 2], 'conditions': {2: 0}}
        """
        plain = [_plain(n) for n in self.names]
        return {
            "global_candidates": [plain[i] for i in self.global_idx],
            "subtasks": [plain[i] for i in self.subtask_idx],
            "conditions": {plain[s]: plain[c]
                           for s, c in zip(self.subtask_idx, self.condition_idx) if c >= 0},
        }


def _plain(name):
    """A column identifier as a plain Python ``str`` or ``int`` (not a NumPy scalar)."""
    if isinstance(name, (numbers.Integral, np.integer)):
        return int(name)
    return str(name)


def _resolve_one(ident, names, param):
    n = len(names)
    if isinstance(ident, (bool, np.bool_)):
        raise ValueError(f"{param}: {ident!r} is not a proposition name or index")
    if isinstance(ident, (numbers.Integral, np.integer)):
        if not 0 <= int(ident) < n:
            raise ValueError(
                f"{param}: proposition index {int(ident)} is out of range for {n} propositions"
            )
        return int(ident)
    try:
        return names.index(ident)
    except ValueError:
        raise ValueError(
            f"{param}: unknown proposition {ident!r}; known propositions are "
            f"{names[:20]}{' ...' if n > 20 else ''}"
        ) from None


def resolve_propositions(value, names, param):
    """Resolve a list of proposition names or indices to column indices.

    Parameters
    ----------
    value : list of str or int, or None
        Propositions, by name or column index; ``None`` means every column.
    names : list
        Identifier of every column (proposition names, or ``0..n_props-1``).
    param : str
        The parameter's name, used in messages.

    Returns
    -------
    indices : ndarray of int64
        Column indices, in the order of ``value``.

    Raises
    ------
    ValueError
        For an unknown name, an index out of range, a repeated proposition or a ``value``
        that is not a list.

    Examples
    --------
    >>> resolve_propositions(["c", 0], ["a", "b", "c"], "subtasks").tolist()
    [2, 0]
    >>> resolve_propositions(None, ["a", "b"], "subtasks").tolist()
    [0, 1]
    """
    if value is None:
        return np.arange(len(names), dtype=np.int64)
    if isinstance(value, (str, bytes)) or not hasattr(value, "__iter__"):
        raise ValueError(
            f"{param} must be None or a list of proposition names or indices, got {value!r}"
        )
    idx = [_resolve_one(v, names, param) for v in value]
    seen = set()
    for v, i in zip(value, idx):
        if i in seen:
            raise ValueError(f"{param}: proposition {v!r} is listed more than once")
        seen.add(i)
    return np.asarray(idx, dtype=np.int64)


def resolve_roles(global_candidates, subtasks, conditions, n_props, feature_names=None):
    """Resolve role parameters (names or indices) to column indices, with clear errors.

    Parameters
    ----------
    global_candidates : list of str or int, or None
        Propositions that may appear in ``G(p)`` clauses; ``None``: every column.
    subtasks : list of str or int, or None
        Subtask propositions; ``None``: every column.
    conditions : mapping or None
        Subtask -> condition proposition (``None`` as a value: no condition).
    n_props : int
        Number of columns.
    feature_names : sequence of str, default=None
        Column names; without them, propositions are named by their index.

    Returns
    -------
    roles : Roles

    Raises
    ------
    ValueError
        Naming the parameter and the proposition at fault (an unknown proposition, one
        listed twice, a condition for a proposition that is not a subtask, a subtask that is
        its own condition).

    Examples
    --------
    >>> roles = resolve_roles(["a"], ["b", "c"], {"c": "a"}, 3, ["a", "b", "c"])
    >>> roles.global_idx.tolist(), roles.subtask_idx.tolist(), roles.condition_idx.tolist()
    ([0], [1, 2], [-1, 0])
    >>> roles.condition_names()
    {'c': 'a'}
    """
    names = list(feature_names) if feature_names is not None else list(range(n_props))
    g = resolve_propositions(global_candidates, names, "global_candidates")
    s = resolve_propositions(subtasks, names, "subtasks")
    cond = np.full(len(s), -1, dtype=np.int64)
    if conditions is not None:
        if not isinstance(conditions, Mapping):
            raise ValueError(
                f"conditions must be None or a mapping subtask -> condition proposition, got "
                f"{type(conditions).__name__}"
            )
        position = {int(c): k for k, c in enumerate(s)}
        for w, c in conditions.items():
            wi = _resolve_one(w, names, "conditions")
            if wi not in position:
                raise ValueError(f"conditions: {w!r} is not one of the subtasks")
            if c is None:
                continue
            ci = _resolve_one(c, names, f"conditions[{w!r}]")
            if ci == wi:
                raise ValueError(
                    f"conditions[{w!r}]: subtask {names[wi]!r} cannot be its own condition "
                    f"(the clause would read {names[wi]} -> F({names[wi]}), which always "
                    "holds); give another proposition, or None for no condition"
                )
            cond[position[wi]] = ci
    return Roles(g, s, cond, names)
