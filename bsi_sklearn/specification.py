"""The `Specification` value type: one formula of the BSI template."""

from __future__ import annotations

from collections.abc import Hashable, Iterable, Mapping

import numpy as np

from bsi_sklearn._trace_values import trace_columns

__all__ = ["Specification", "transitive_closure"]


def _sort_key(x):
    # Identifiers may mix ints and strings; sort by type name first so ordering never fails.
    return (type(x).__name__, x)


def transitive_closure(pairs):
    """Return the transitive closure of a precedence relation.

    Parameters
    ----------
    pairs : iterable of (a, b)
        ``(a, b)`` means *a precedes b*.

    Returns
    -------
    closure : frozenset of (a, b)

    Raises
    ------
    ValueError
        If the relation has a cycle (including ``(a, a)``).

    Examples
    --------
    >>> sorted(transitive_closure([("a", "b"), ("b", "c")]))
    [('a', 'b'), ('a', 'c'), ('b', 'c')]
    """
    succ: dict = {}
    for pair in pairs:
        try:
            a, b = pair
        except (TypeError, ValueError):
            raise ValueError(f"order {pair!r} is not a pair (a, b)") from None
        if a == b:
            raise ValueError(f"order ({a!r}, {b!r}) relates a subtask to itself")
        succ.setdefault(a, set()).add(b)
    closure = set()
    for start in succ:
        stack, seen = list(succ[start]), set()
        while stack:
            node = stack.pop()
            if node in seen:
                continue
            seen.add(node)
            stack.extend(succ.get(node, ()))
        if start in seen:
            raise ValueError(f"the orders contain a cycle through subtask {start!r}")
        closure.update((start, d) for d in seen)
    return frozenset(closure)


class Specification:
    """An LTL formula ``G(tau) & (pi -> F omega) & (pi_a -> (!omega_b U omega_a))``.

    A frozen, hashable value: two specifications built from the same sets are equal.

    Parameters
    ----------
    globals : iterable of hashable, default=()
        Propositions ``tau`` required to hold at every step: clauses ``G(tau)``.
    eventuals : iterable of hashable, default=()
        Subtasks ``w`` that must eventually complete when their condition holds:
        clauses ``pi_w -> F(omega_w)``.
    orders : iterable of (a, b), default=()
        Precedence pairs, *a precedes b*: clauses ``pi_a -> (!omega_b U omega_a)``.
        Stored transitively closed; a cycle raises ``ValueError``.
    conditions : mapping, default=None
        Subtask -> condition proposition ``pi_w``; subtasks without an entry have
        ``pi_w = true``. Entries for subtasks the formula does not mention are dropped.

    Attributes
    ----------
    globals, eventuals : frozenset
    orders : frozenset of tuple
    conditions : dict
        Read-only copy of the relevant conditions.

    Examples
    --------
    >>> spec = Specification(globals=["safe"], eventuals=["a", "b"],
    ...                      orders=[("a", "b")], conditions={"b": "b_ok"})
    >>> spec.n_conjuncts
    4
    >>> print(spec.to_ltl())
    G(safe) & F(a) & (b_ok -> F(b)) & (!b U a)
    >>> import numpy as np
    >>> trace = np.array([[1, 0, 0, 1], [1, 1, 0, 1], [1, 1, 1, 1]])  # safe, a, b, b_ok
    >>> spec.satisfied_by(trace, feature_names=["safe", "a", "b", "b_ok"])
    True
    """

    __slots__ = ("globals", "eventuals", "orders", "_conditions", "_hash")

    def __init__(self, globals=(), eventuals=(), orders=(), conditions=None):
        g = frozenset(_as_iterable(globals, "globals"))
        e = frozenset(_as_iterable(eventuals, "eventuals"))
        o = transitive_closure(_as_iterable(orders, "orders"))
        for ident in [*g, *e, *(x for p in o for x in p)]:
            if not isinstance(ident, Hashable):
                raise ValueError(f"identifier {ident!r} is not hashable")
        conds = {}
        if conditions is not None:
            if not isinstance(conditions, Mapping):
                raise ValueError("conditions must be a mapping subtask -> proposition")
            mentioned = e | {a for a, _ in o}
            conds = {w: c for w, c in conditions.items() if w in mentioned and c is not None}
        object.__setattr__(self, "globals", g)
        object.__setattr__(self, "eventuals", e)
        object.__setattr__(self, "orders", o)
        object.__setattr__(self, "_conditions", tuple(sorted(conds.items(), key=_pair_key)))
        object.__setattr__(
            self, "_hash", hash((g, e, o, self._conditions))
        )

    def __setattr__(self, name, value):
        raise AttributeError("Specification is immutable")

    def __reduce__(self):
        return (
            Specification,
            (tuple(self.globals), tuple(self.eventuals), tuple(self.orders), self.conditions),
        )

    @property
    def conditions(self):
        """Subtask -> condition proposition for the subtasks this formula mentions."""
        return dict(self._conditions)

    @property
    def n_conjuncts(self):
        """Number of clauses ``|tau| + |W1| + |W2|``."""
        return len(self.globals) + len(self.eventuals) + len(self.orders)

    def clauses(self):
        """Return the clause keys: ``("G", p)``, ``("F", w)``, ``("U", a, b)``.

        These are the elements the Jaccard similarity of the paper's eq. (13) compares.
        """
        return frozenset(
            [("G", p) for p in self.globals]
            + [("F", w) for w in self.eventuals]
            + [("U", a, b) for a, b in self.orders]
        )

    def __eq__(self, other):
        if not isinstance(other, Specification):
            return NotImplemented
        return (
            self.globals == other.globals
            and self.eventuals == other.eventuals
            and self.orders == other.orders
            and self._conditions == other._conditions
        )

    def __hash__(self):
        return self._hash

    def __repr__(self):
        parts = [
            f"globals={sorted(self.globals, key=_sort_key)!r}",
            f"eventuals={sorted(self.eventuals, key=_sort_key)!r}",
            f"orders={sorted(self.orders, key=_pair_key)!r}",
        ]
        if self._conditions:
            parts.append(f"conditions={self.conditions!r}")
        return f"Specification({', '.join(parts)})"

    def clause_strings(self, latex=False):
        """Render every clause as a string, in a stable order (G, then F, then U)."""
        g_op, f_op, u_op, not_op, imp = (
            (r"\mathbf{G}", r"\mathbf{F}", r"\,\mathbf{U}\,", r"\neg ", r" \rightarrow ")
            if latex
            else ("G", "F", " U ", "!", " -> ")
        )
        cond = self.conditions
        out = [f"{g_op}({_fmt(p, latex)})" for p in sorted(self.globals, key=_sort_key)]
        for w in sorted(self.eventuals, key=_sort_key):
            body = f"{f_op}({_fmt(w, latex)})"
            out.append(f"({_fmt(cond[w], latex)}{imp}{body})" if w in cond else body)
        for a, b in sorted(self.orders, key=_pair_key):
            body = f"({not_op}{_fmt(b, latex)}{u_op}{_fmt(a, latex)})"
            out.append(f"({_fmt(cond[a], latex)}{imp}{body})" if a in cond else body)
        return out

    def to_ltl(self, latex=False):
        """Render the formula as LTL text (ASCII by default, LaTeX with ``latex=True``).

        The empty specification renders as ``true``.
        """
        parts = self.clause_strings(latex=latex)
        if not parts:
            return r"\top" if latex else "true"
        return (r" \wedge " if latex else " & ").join(parts)

    def __str__(self):
        return self.to_ltl()

    def to_ltlf(self, dialect="spot", atoms=None):
        """The formula as text for Spot (``"spot"``) or LTLf2DFA / flloat (``"ltlf2dfa"``).

        See :func:`bsi_sklearn.automaton.to_ltlf`; on this template the text means the same
        under LTLf (the finite trace) and LTL (the last state repeating forever).
        """
        from bsi_sklearn.automaton import to_ltlf

        return to_ltlf(self, dialect=dialect, atoms=atoms)

    def to_automaton(self):
        """The minimal DFA accepting exactly the traces that satisfy the formula.

        Returns
        -------
        automaton : bsi_sklearn.automaton.SpecificationAutomaton
            ``automaton.accepts(trace)`` equals :meth:`satisfied_by`; ``automaton.to_dot()``
            exports it.

        Notes
        -----
        Built by the project as the product of the clauses' small automata (no optional
        package): milliseconds when the subtasks are ordered; the size grows as 2^k with k
        mutually unordered eventual subtasks, as any DFA of the formula must.
        """
        from bsi_sklearn.automaton import SpecificationAutomaton

        return SpecificationAutomaton(self)

    def satisfied_by(self, trace, feature_names=None):
        """Evaluate the formula at t=0 on a finite trace (last state repeats forever).

        Parameters
        ----------
        trace : array-like of shape (T, n_props) or pandas.DataFrame
            Boolean (or 0/1) trace, rows are time steps.
        feature_names : sequence, default=None
            Column names of ``trace``; taken from the DataFrame columns when omitted. Integer
            identifiers that are not column names are read as column indices.

        Returns
        -------
        satisfied : bool
        """
        columns, arr = trace_columns(trace, feature_names)

        def col(ident):
            if columns is not None and ident in columns:
                return arr[:, columns[ident]]
            if columns is not None and not isinstance(ident, (int, np.integer)):
                raise ValueError(f"proposition {ident!r} is not a column of the trace")
            if isinstance(ident, (int, np.integer)) and 0 <= ident < arr.shape[1]:
                return arr[:, int(ident)]
            raise ValueError(
                f"proposition {ident!r} is not a column index of a trace with "
                f"{arr.shape[1]} columns; pass feature_names"
            )

        cond = self.conditions

        def condition(w):
            return True if w not in cond else bool(col(cond[w])[0])

        if not all(col(p).all() for p in self.globals):
            return False
        if not all(not condition(w) or col(w).any() for w in self.eventuals):
            return False
        for a, b in self.orders:
            if not condition(a):
                continue
            ca, cb = col(a), col(b)
            if not ca.any():
                return False
            first_a = int(np.argmax(ca))
            if cb[:first_a].any():
                return False
        return True


def _as_iterable(value, name):
    if isinstance(value, (str, bytes)) or not isinstance(value, Iterable):
        raise ValueError(f"{name} must be an iterable of identifiers, got {value!r}")
    return list(value)


def _pair_key(pair):
    # Orders (a, b) and condition items (subtask, proposition) alike.
    return (_sort_key(pair[0]), _sort_key(pair[1]))


def _fmt(ident, latex):
    text = str(ident)
    if latex:
        text = text.replace("\\", r"\textbackslash{}").replace("_", r"\_")
        return rf"\mathit{{{text}}}"
    return text
