"""The truth of a template on finite traces, in LTLf: the value type's own small evaluator.

:meth:`~bsi_sklearn.specification.Specification.satisfied_by` and the pattern-clause node of
:mod:`bsi_sklearn.ltl` read a pattern clause with it; the model computes the same truth with
numba kernels for fitting (:func:`bsi_sklearn.model.patterns.pattern_truth`, which the tests
compare it with), and the specification layer may not import the model.
"""

import numpy as np

from bsi_sklearn.specification.templates import OPCODES, get_template, parse_ltlf

__all__ = ["holds", "step_truth"]

_ATOM, _TRUE, _FALSE, _NOT, _AND, _OR, _IMPLIES, _EQUIV = (
    OPCODES[k] for k in ("atom", "true", "false", "not", "and", "or", "implies", "equiv"))
_NEXT, _WEAK_NEXT, _EVENTUALLY, _GLOBALLY, _UNTIL = (
    OPCODES[k] for k in ("next", "weak_next", "eventually", "globally", "until"))


def step_truth(template, values, lengths=None):
    """Truth of a template at every step of finite traces, in LTLf (a backward pass).

    The small pure-NumPy reading of a template's formula that the value type evaluates with
    (:meth:`~bsi_sklearn.specification.Specification.satisfied_by`); the model's kernels
    (:func:`bsi_sklearn.model.patterns.pattern_truth`) compute the same truth, faster, for
    fitting. Step ``t`` reads the formula on the suffix that starts at ``t``.

    Parameters
    ----------
    template : str or Template
    values : array-like of shape (T, n_slots) or (n_traces, T, n_slots)
        The truth of each slot's proposition at each step, in the template's slot order.
    lengths : array-like of shape (n_traces,), default=None
        With a 3-D ``values``: the length of each trace, ``1 <= lengths <= T``; a trace's steps
        from ``lengths - 1`` on are each read as a last step (so padding a trace by repeating
        its last state leaves its truth there as at its last step). ``None``: all ``T`` steps.

    Returns
    -------
    truth : ndarray of bool, of shape (T,) or (n_traces, T)

    Raises
    ------
    ValueError
        For a trace without a step, or ``values`` whose last axis is not the slots.

    Examples
    --------
    >>> import numpy as np
    >>> step_truth("Precedence", np.array([[0, 1], [1, 0], [0, 1]])).tolist()  # a, b
    [False, True, False]
    """
    t = get_template(template)
    arr = np.asarray(values).astype(bool)
    single = arr.ndim == 2
    if single:
        arr = arr[None]
    if arr.ndim != 3 or arr.shape[2] != len(t.slots):
        raise ValueError(f"values for the template {t.name!r} must have shape (T, "
                         f"{len(t.slots)}) or (n_traces, T, {len(t.slots)}): one column per "
                         f"slot ({', '.join(t.slots)}), got shape {np.shape(values)}")
    n, steps = arr.shape[:2]
    if steps == 0:
        raise ValueError("a trace has at least one step; got an empty one")
    if lengths is None:
        lengths = np.full(n, steps)
    lengths = np.asarray(lengths, dtype=np.int64).reshape(-1)
    if lengths.shape[0] != n or np.any(lengths < 1) or np.any(lengths > steps):
        raise ValueError(f"lengths must give each of the {n} traces a length in 1..{steps}")
    # at_end[:, i]: step i is the last step (or past it): no next step to read.
    at_end = np.arange(steps)[None, :] >= (lengths[:, None] - 1)
    atoms = {slot: arr[:, :, k] for k, slot in enumerate(t.slots)}
    out = _tree_steps(parse_ltlf(t.formula), atoms, at_end)
    return out[0] if single else out


def holds(template, values):
    """Whether one finite trace satisfies a template at its first step (LTLf).

    Parameters
    ----------
    template : str or Template
    values : array-like of shape (T, n_slots)
        The truth of each slot's proposition at each step, in the template's slot order.

    Returns
    -------
    satisfied : bool

    Examples
    --------
    >>> import numpy as np
    >>> holds("Response", np.array([[1, 0], [0, 1]])), holds("Response", [[0, 1], [1, 0]])
    (True, False)
    """
    values = np.asarray(values)
    if values.ndim != 2:
        raise ValueError(f"values must be 2-D (steps, slots), got shape {values.shape}")
    return bool(step_truth(template, values)[0])


def _tree_steps(node, atoms, at_end):
    """Truth of a parsed formula at every step: ``(n_traces, T)`` booleans."""
    op = node[0]
    if op == _ATOM:
        return atoms[node[1]]
    if op in (_TRUE, _FALSE):
        return np.full(at_end.shape, op == _TRUE)
    kids = [_tree_steps(child, atoms, at_end) for child in node[1:]]
    if op == _NOT:
        return ~kids[0]
    if op == _AND:
        return kids[0] & kids[1]
    if op == _OR:
        return kids[0] | kids[1]
    if op == _IMPLIES:
        return ~kids[0] | kids[1]
    if op == _EQUIV:
        return kids[0] == kids[1]
    v = kids[0]
    out = np.empty_like(v)
    if op in (_NEXT, _WEAK_NEXT):
        # No next step: strong next is false there, weak next true.
        out[:, :-1] = v[:, 1:]
        out[:, -1] = False
        return np.where(at_end, op == _WEAK_NEXT, out)
    # F, G, U, R: one step from the end backwards, each from the one after it.
    later = np.zeros(v.shape[0], dtype=bool)
    for i in range(v.shape[1] - 1, -1, -1):
        more = ~at_end[:, i]
        if op == _EVENTUALLY:
            later = v[:, i] | (more & later)
        elif op == _GLOBALLY:
            later = v[:, i] & (~more | later)
        elif op == _UNTIL:
            later = kids[1][:, i] | (v[:, i] & more & later)
        else:  # release: psi here, and phi here or psi's release at the next step
            later = kids[1][:, i] & (v[:, i] | ~more | later)
        out[:, i] = later
    return out
