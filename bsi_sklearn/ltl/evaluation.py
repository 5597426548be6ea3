"""Truth of a formula over ragged traces: padded, length-grouped evaluation of the tree."""

from __future__ import annotations

import numpy as np

__all__ = ["evaluate_traces"]

# Padded evaluation holds (demos x steps) booleans per subformula; chunks stay below this.
_MAX_CELLS = 4_000_000


def evaluate_traces(formula, traces, feature_names=None):
    """Truth of ``formula`` at ``t = 0`` on every trace of ``traces``.

    Demonstrations are grouped by length and padded by repeating their last state, which
    leaves the infinite word (and so every truth value) unchanged; each group is a boolean
    cube ``(n, t_max, n_atoms)`` that every subformula evaluates on at once.
    Pattern clauses (:class:`~bsi_sklearn.ltl.formula.Pattern`, read in LTLf on the
    finite trace) are given each trace's length, so the padding leaves them unchanged too.

    Parameters
    ----------
    formula : Formula
        The formula.
    traces : Traces
        Validated traces (:func:`bsi_sklearn.data.traces.check_traces`).
    feature_names : sequence of str, default=None
        Proposition names of the columns; default ``traces.feature_names``.

    Returns
    -------
    satisfied : ndarray of shape (n_demos,), dtype bool

    Examples
    --------
    >>> import numpy as np
    >>> from bsi_sklearn.ltl import parse_ltl
    >>> from bsi_sklearn.data.traces import check_traces
    >>> traces = check_traces([np.array([[0, 1], [1, 1]]), np.array([[0, 0]])])
    >>> evaluate_traces(parse_ltl("F(a) & G(b)"), traces, ["a", "b"])
    array([ True, False])
    """
    names = feature_names if feature_names is not None else traces.feature_names
    columns = _resolve_atoms(formula.atoms, names, traces.n_props)
    atom_list = sorted(columns)
    used = traces.data[:, [columns[a] for a in atom_list]].astype(bool)
    columns = {a: k for k, a in enumerate(atom_list)}
    lengths = traces.lengths
    result = np.empty(traces.n_demos, dtype=bool)
    order = np.argsort(lengths, kind="stable")
    start = 0
    while start < len(order):
        # Group demonstrations of similar length; pad each by repeating its last state,
        # which leaves the infinite word (and so every truth value) unchanged.
        t_max = int(lengths[order[start]])
        stop = start + 1
        while stop < len(order):
            t_next = int(lengths[order[stop]])
            if (stop - start + 1) * t_next > _MAX_CELLS and stop > start:
                break
            t_max = t_next
            stop += 1
        idx = order[start:stop]
        steps = np.minimum(np.arange(t_max)[None, :], lengths[idx, None] - 1)
        rows = traces.offsets[idx, None] + steps
        cube = used[rows]  # (n, t_max, n_atoms)
        # A pattern clause (LTLf) reads where each padded trace ends.
        cache = {"lengths": lengths[idx]}
        value = formula._eval(cube, columns, cache)
        result[idx] = value[:, 0]
        start = stop
    return result


def _resolve_atoms(atoms, names, n_props):
    columns = {}
    lookup = None
    if names is not None:
        names = [str(n) for n in names]
        if len(names) != n_props:
            raise ValueError(
                f"feature_names has {len(names)} entries for traces with {n_props} propositions"
            )
        lookup = {n: i for i, n in enumerate(names)}
    for atom in sorted(atoms):
        if lookup is not None and atom in lookup:
            columns[atom] = lookup[atom]
        elif atom.isdecimal() and int(atom) < n_props:
            columns[atom] = int(atom)
        elif lookup is None:
            raise ValueError(
                f"proposition {atom!r} cannot be resolved: the traces have no proposition "
                "names; pass feature_names or DataFrames"
            )
        else:
            raise ValueError(
                f"proposition {atom!r} is not among the trace propositions "
                f"{names[:20]}{' ...' if len(names) > 20 else ''}"
            )
    return columns
