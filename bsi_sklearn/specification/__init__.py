"""The `Specification` value type: one formula of the BSI template, and how it is written out.

``ltlf_export`` writes a specification as LTLf text for Spot, flloat and LTLf2DFA
(:func:`~bsi_sklearn.specification.ltlf_export.to_ltlf`,
:class:`~bsi_sklearn.specification.ltlf_export.SpecificationAutomaton`); ``automaton`` builds
its minimal DFA (:func:`~bsi_sklearn.specification.automaton.specification_dfa`). Both read
only the value, so they sit beside it, below :mod:`bsi_sklearn.ltl`, which reads a formula as
a specification (``docs/architecture.md``, "Layers").
"""

from __future__ import annotations

from collections.abc import Hashable, Iterable, Mapping

import numpy as np

from bsi_sklearn._literals import (
    clause_form,
    literal,
    negation_reader,
    readable_atom,
    render_clause,
)
from bsi_sklearn.data.values import trace_columns
from bsi_sklearn.specification.implied_patterns import implied_patterns
from bsi_sklearn.specification.template_truth import holds
from bsi_sklearn.specification.templates import TEMPLATES, get_template, pattern_order

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
    patterns : iterable of (template, propositions), default=()
        Pattern clauses (DESIGN §12): a template of
        :mod:`bsi_sklearn.specification.templates` (a catalogue name such as ``"Response"``,
        or LTLf text with placeholders) and the propositions filling its slots, in slot
        order. Stored by the template's name, the propositions sorted for a symmetric
        template (``Choice(a, b)`` is ``Choice(b, a)``).

    Attributes
    ----------
    globals, eventuals : frozenset
    orders : frozenset of tuple
    conditions : dict
        Read-only copy of the relevant conditions.
    patterns : frozenset of (str, tuple)
        ``(template name, propositions)`` of every pattern clause.

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

    __slots__ = ("globals", "eventuals", "orders", "_conditions", "patterns", "_hash")

    def __init__(self, globals=(), eventuals=(), orders=(), conditions=None, patterns=()):
        g = frozenset(_as_iterable(globals, "globals"))
        e = frozenset(_as_iterable(eventuals, "eventuals"))
        o = transitive_closure(_as_iterable(orders, "orders"))
        pats = frozenset(_pattern_key(item) for item in _as_iterable(patterns, "patterns"))
        for ident in [*g, *e, *(x for p in o for x in p), *(x for _, p in pats for x in p)]:
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
        object.__setattr__(self, "patterns", pats)
        # Without patterns, the hash of the paper's template as it always was.
        key = (g, e, o, self._conditions)
        object.__setattr__(self, "_hash", hash((*key, pats) if pats else key))

    def __setattr__(self, name, value):
        raise AttributeError("Specification is immutable")

    def __reduce__(self):
        return (
            Specification,
            (tuple(self.globals), tuple(self.eventuals), tuple(self.orders), self.conditions,
             tuple(self.patterns)),
        )

    @property
    def conditions(self):
        """Subtask -> condition proposition for the subtasks this formula mentions."""
        return dict(self._conditions)

    @property
    def n_conjuncts(self):
        """Number of clauses ``|tau| + |W1| + |W2|``, and the pattern clauses."""
        return len(self.globals) + len(self.eventuals) + len(self.orders) + len(self.patterns)

    def clauses(self):
        """Return the clause keys: ``("G", p)``, ``("F", w)``, ``("U", a, b)``, ``("P", t, ps)``.

        These are the elements the Jaccard similarity of the paper's eq. (13) compares. A
        pattern clause's key is ``("P", template name, propositions)``, as in
        :attr:`patterns` (a symmetric template's propositions sorted).

        Examples
        --------
        >>> sorted(Specification(globals=["s"], patterns=[("Response", ("a", "b"))]).clauses())
        [('G', 's'), ('P', 'Response', ('a', 'b'))]
        """
        return frozenset(
            [("G", p) for p in self.globals]
            + [("F", w) for w in self.eventuals]
            + [("U", a, b) for a, b in self.orders]
            + [("P", name, props) for name, props in self.patterns]
        )

    def __eq__(self, other):
        if not isinstance(other, Specification):
            return NotImplemented
        return (
            self.globals == other.globals
            and self.eventuals == other.eventuals
            and self.orders == other.orders
            and self._conditions == other._conditions
            and self.patterns == other.patterns
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
        if self.patterns:
            parts.append(f"patterns={sorted(self.patterns, key=pattern_order)!r}")
        return f"Specification({', '.join(parts)})"

    def implied_orders(self):
        """The order clauses the rest of the formula implies: what the chain form leaves out.

        An order ``(a, c)`` is implied when the other orders kept lead from ``a`` to ``c``
        through subtasks ``b`` whose conditions hold whenever ``pi_a`` does: ``b`` has no
        condition, its condition is a global ``G(pi_b)`` of the formula, or it is ``pi_a``
        itself. Then ``pi_a`` makes every clause of the path active, each of them puts the
        first step of its subtask no later than the next one's, and ``a`` does happen, so
        ``pi_a -> (!c U a)`` holds. Without conditions this is the transitive reduction of
        the order relation. Orders are examined in a fixed sequence and each one dropped only
        if the orders still kept imply it, so the formula without the implied orders means
        exactly what the full formula means.

        Returns
        -------
        implied : frozenset of (a, b)

        Examples
        --------
        >>> chain = Specification(orders=[("a", "b"), ("b", "c")])
        >>> sorted(chain.implied_orders())
        [('a', 'c')]
        >>> # b's own condition may be false when a's holds: c may then come before a
        >>> sorted(Specification(orders=chain.orders, conditions={"b": "b_ok"}).implied_orders())
        []
        """
        cond = self.conditions

        def holds_with(a):
            # the subtasks whose condition holds whenever a's does
            return lambda b: b not in cond or cond[b] in self.globals or cond[b] == cond.get(a)

        kept = set(self.orders)
        for a, c in sorted(self.orders, key=_pair_key):
            kept.discard((a, c))
            if not _reaches(kept, a, c, holds_with(a)):
                kept.add((a, c))
        return frozenset(self.orders - kept)

    def implied_clauses(self):
        """The clauses the rest of the formula implies: what the readable forms leave out.

        The orders :meth:`implied_orders` gives; the eventual clause and the orders of a
        subtask ``w`` that a clause ``G(w)`` holds throughout (``w`` holds at the first step,
        so ``F(w)`` and ``(!b U w)`` do, under any condition); and the pattern clauses the
        other clauses imply together
        (:func:`~bsi_sklearn.specification.implied_patterns.implied_patterns`). Each is
        implied by clauses that stay, so the formula without them means the same.

        Returns
        -------
        keys : frozenset of clause keys

        Examples
        --------
        >>> spec = Specification(globals=["a"], eventuals=["a", "b"],
        ...                      orders=[("a", "b"), ("b", "c"), ("b", "d"), ("c", "d")])
        >>> sorted(spec.implied_clauses())  # the orders are closed: a precedes c and d too
        [('F', 'a'), ('U', 'a', 'b'), ('U', 'a', 'c'), ('U', 'a', 'd'), ('U', 'b', 'd')]
        """
        out = {("U", a, b) for a, b in self.implied_orders()}
        out |= {("F", w) for w in self.eventuals if w in self.globals}
        out |= {("U", a, b) for a, b in self.orders if a in self.globals}
        return frozenset(out | (implied_patterns(self) if self.patterns else frozenset()))

    def clause_strings(self, latex=False, *, chains=False):
        r"""Render every clause as a string, in a stable order (G, F, U, then the patterns).

        With ``chains=True`` the orders of :meth:`implied_orders` are left out. A pattern
        clause is written by its template's name and its propositions, ``Response(a, b)``; a
        user template (LTLf text) in braces before them, ``{G(x -> F(y))}(a, b)``: the
        template's own LTLf (its ``X`` the strong next) is not this text's LTL, whose ``X``
        reads the repeated last state. :func:`bsi_sklearn.ltl.parse_ltl` reads both forms back.

        Examples
        --------
        >>> spec = Specification(globals=["s"], patterns=[("Response", ("a", "b")),
        ...                                               ("G(x -> WX(!x))", ["c"])])
        >>> spec.clause_strings()
        ['G(s)', 'Response(a, b)', '{G(x -> WX(!x))}(c)']
        >>> print(spec.clause_strings(latex=True)[1])
        \mathrm{Response}(\mathit{a}, \mathit{b})
        """
        return [text for _, text in self._clause_texts(latex, chains)]

    def _clause_texts(self, latex=False, chains=False):
        """``(clause key, text)`` for every clause, in the order of :meth:`clause_strings`."""
        g_op, f_op, u_op, not_op, imp = (
            (r"\mathbf{G}", r"\mathbf{F}", r"\,\mathbf{U}\,", r"\neg ", r" \rightarrow ")
            if latex
            else ("G", "F", " U ", "!", " -> ")
        )
        cond = self.conditions
        out = [(("G", p), f"{g_op}({_fmt(p, latex)})")
               for p in sorted(self.globals, key=_sort_key)]
        for w in sorted(self.eventuals, key=_sort_key):
            body = f"{f_op}({_fmt(w, latex)})"
            out.append((("F", w), f"({_fmt(cond[w], latex)}{imp}{body})" if w in cond else body))
        implied = self.implied_orders() if chains else frozenset()
        for a, b in sorted(self.orders - implied, key=_pair_key):
            body = f"({not_op}{_fmt(b, latex)}{u_op}{_fmt(a, latex)})"
            out.append((("U", a, b),
                        f"({_fmt(cond[a], latex)}{imp}{body})" if a in cond else body))
        out += [(("P", name, props), _pattern_text(name, [_fmt(p, latex) for p in props], latex))
                for name, props in sorted(self.patterns, key=pattern_order)]
        return out

    def to_ltl(self, latex=False, *, chains=False):
        """Render the formula as LTL text (ASCII by default, LaTeX with ``latex=True``).

        The empty specification renders as ``true``. The text lists every clause, the orders
        implied by others included (the closed order relation the specification stores): the
        form the posterior file records. ``chains=True`` leaves out the implied orders
        (:meth:`implied_orders`): a shorter text of the same formula, ``(!c U b) & (!b U a)``
        without ``(!c U a)``.

        Examples
        --------
        >>> spec = Specification(orders=[("a", "b"), ("b", "c")])
        >>> print(spec.to_ltl())
        (!b U a) & (!c U a) & (!c U b)
        >>> print(spec.to_ltl(chains=True))
        (!b U a) & (!c U b)
        """
        return _join(self.clause_strings(latex=latex, chains=chains), latex)

    def readable(self, vacuous=(), *, negations=None):
        """The formula as a person reads it: orders as chains, untested clauses set apart.

        Parameters
        ----------
        vacuous : iterable of clause keys, default=()
            Clauses the data could not test (``("G", p)``, ``("F", w)``, ``("U", a, b)``,
            ``("P", template, propositions)``;
            ``BSIClassifier.vacuous_clauses_``: satisfied by every training demonstration,
            acceptable or not). Keys of clauses the formula does not have are ignored.
        negations : None, False or mapping, default=None
            Which propositions are negations of others: by default a name ``"!p"`` is the
            negation of ``p`` (the columns of
            :class:`~bsi_sklearn.data.preprocessing.NegationAugmenter` and
            :class:`~bsi_sklearn.io.EventLogEncoder`); a mapping ``{negated: proposition}``
            (their ``negations_``) names exactly those; ``False`` none.

        Returns
        -------
        text : str
            ``to_ltl()`` without the vacuous clauses and without the clauses the rest
            implies (:meth:`implied_clauses`: the orders the chain form leaves out, the
            eventual and order clauses of a subtask a ``G`` clause holds throughout, the
            pattern clauses the others imply; the formula means the same), followed, when the
            formula has
            some, by ``"  [untested: ...]"`` listing them joined by ``&``. The shown formula
            and the untested one together are the full formula: ``to_ltl()`` gives it in one
            piece. A negation is written ``!p``, never ``!!p``: an order on a negated
            column, ``(!"!p" U a)``, reads ``(p U a)``, and an order between a proposition and
            its own negation is written as the simpler formula it equals, ``(!!p U p)`` as
            ``p`` (``p`` at the first step) and ``(!p U !p)`` as ``!p``
            (:mod:`bsi_sklearn._literals` lists the rules). A proposition named ``!x`` that
            ``negations`` does not make a negation is written in quotes, ``"!x"``. The text
            reads back with :func:`bsi_sklearn.ltl.parse_ltl` as the same formula over the
            propositions themselves (an equivalent one where implied pattern clauses were
            left out).

        Examples
        --------
        >>> spec = Specification(globals=["safe"], eventuals=["a", "b"],
        ...                      orders=[("a", "b"), ("b", "c")])
        >>> print(spec.readable())
        G(safe) & F(a) & F(b) & (!b U a) & (!c U b)
        >>> print(spec.readable(vacuous=[("G", "safe"), ("F", "b")]))
        F(a) & (!b U a) & (!c U b)  [untested: G(safe) & F(b)]
        >>> negated = Specification(globals=["!r"], orders=[("a", "!p"), ("p", "!p")])
        >>> print(negated.to_ltl())
        G(!r) & (!!p U a) & (!!p U p)
        >>> print(negated.readable())
        G(!r) & (p U a) & p
        """
        untested = _clause_keys(vacuous)
        texts = self._readable_texts(negations)
        shown = _join([t for k, t in texts if k not in untested], False)
        apart = [t for k, t in texts if k in untested]
        return f"{shown}  [untested: {' & '.join(apart)}]" if apart else shown

    def _readable_texts(self, negations):
        """``(clause key, text)`` of the chain form over literals (see :meth:`readable`)."""
        negates = negation_reader(negations, "readable")
        cond = self.conditions
        implied = self.implied_clauses()
        keys = ([("G", p) for p in sorted(self.globals, key=_sort_key)]
                + [("F", w) for w in sorted(self.eventuals, key=_sort_key)]
                + [("U", a, b) for a, b in sorted(self.orders, key=_pair_key)])
        out = [(key, render_clause(clause_form(key, cond, negates), readable_atom, _ASCII))
               for key in keys if key not in implied]
        for name, props in sorted(self.patterns, key=pattern_order):
            if ("P", name, props) in implied:
                continue
            # A negated column is the literal !p here too, as in the other clauses.
            lits = [literal(p, negates) for p in props]
            args = [readable_atom(x.atom) if x.positive else f"!{readable_atom(x.atom)}"
                    for x in lits]
            out.append((("P", name, props), _pattern_text(name, args, False)))
        return out

    def __str__(self):
        return self.to_ltl(chains=True)

    def to_ltlf(self, dialect="spot", atoms=None, *, negations=None):
        """The formula as text for Spot (``"spot"``) or LTLf2DFA / flloat (``"ltlf2dfa"``).

        See :func:`bsi_sklearn.specification.ltlf_export.to_ltlf` (a negated column ``"!q"`` is
        written ``!q``, the negation of the atom ``q``); on this template the text means the
        same under LTLf (the finite trace) and LTL (the last state repeating forever).
        """
        from bsi_sklearn.specification.ltlf_export import to_ltlf

        return to_ltlf(self, dialect=dialect, atoms=atoms, negations=negations)

    def to_automaton(self):
        """The minimal DFA accepting exactly the traces that satisfy the formula.

        Returns
        -------
        automaton : bsi_sklearn.specification.ltlf_export.SpecificationAutomaton
            ``automaton.accepts(trace)`` equals :meth:`satisfied_by`; ``automaton.to_dot()``
            exports it.

        Notes
        -----
        Built by the project as the product of the clauses' small automata (no optional
        package): milliseconds when the subtasks are ordered; the size grows as 2^k with k
        mutually unordered eventual subtasks, as any DFA of the formula must.
        """
        from bsi_sklearn.specification.ltlf_export import SpecificationAutomaton

        return SpecificationAutomaton(self)

    def satisfied_by(self, trace, feature_names=None):
        """Evaluate the formula at t=0 on a finite trace (last state repeats forever).

        The pattern clauses are read in LTLf, on the finite trace as it is (their ``X`` is
        false at the last step, ``WX`` true; :func:`~.template_truth.holds`); the other clauses
        mean the same either way.

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
        # Pattern clauses in LTLf on the finite trace as it is (DESIGN §12).
        return all(holds(name, np.stack([col(p) for p in props], axis=1))
                   for name, props in self.patterns)


def _as_iterable(value, name):
    if isinstance(value, (str, bytes)) or not isinstance(value, Iterable):
        raise ValueError(f"{name} must be an iterable of identifiers, got {value!r}")
    return list(value)


def _pattern_key(item):
    """``(template name, propositions)`` of one pattern clause, checked and canonical."""
    try:
        template, props = item
    except (TypeError, ValueError):
        raise ValueError(f"pattern {item!r} is not a pair (template, propositions)") from None
    t = get_template(template)
    props = tuple(_as_iterable(props, f"the propositions of pattern {t.name!r}"))
    if len(props) != len(t.slots):
        raise ValueError(f"pattern {t.name!r} has {len(t.slots)} slots ({', '.join(t.slots)}), "
                         f"got {len(props)} propositions {list(props)}")
    if len(set(props)) != len(props):
        raise ValueError(f"pattern {t.name!r}: a proposition fills two slots in {list(props)}")
    if t.symmetric:
        props = tuple(sorted(props, key=_sort_key))
    return (t.name, props)


def _pair_key(pair):
    # Orders (a, b) and condition items (subtask, proposition) alike.
    return (_sort_key(pair[0]), _sort_key(pair[1]))


def _join(parts, latex):
    if not parts:
        return r"\top" if latex else "true"
    return (r" \wedge " if latex else " & ").join(parts)


def _reaches(orders, start, goal, may_pass):
    """Whether ``orders`` lead from ``start`` to ``goal`` through subtasks ``may_pass`` allows."""
    succ = {}
    for a, b in orders:
        succ.setdefault(a, []).append(b)
    stack, seen = [start], {start}
    while stack:
        for b in succ.get(stack.pop(), ()):
            if b == goal:
                return True
            if b not in seen and may_pass(b):
                seen.add(b)
                stack.append(b)
    return False


def _clause_keys(keys):
    if isinstance(keys, (str, bytes)) or not isinstance(keys, Iterable):
        raise ValueError(f"vacuous must be an iterable of clause keys, got {keys!r}")
    keys = frozenset(keys)
    for key in keys:
        if not (isinstance(key, tuple) and key[:1] in (("G",), ("F",), ("U",), ("P",))
                and len(key) == (3 if key[0] in ("U", "P") else 2)
                and (key[0] != "P" or isinstance(key[2], tuple))):
            raise ValueError(f"vacuous: {key!r} is not a clause key ('G', p), ('F', w), "
                             "('U', a, b) or ('P', template, propositions)")
    return keys


def _pattern_text(name, args, latex):
    """``Name(a, b)`` of a catalogue template, ``{formula}(a, b)`` of a user template."""
    if name in TEMPLATES:
        head = rf"\mathrm{{{name}}}" if latex else name
    elif latex:
        text = name.replace("\\", r"\textbackslash{}").replace("&", r"\&")
        head = rf"\texttt{{\{{{text}\}}}}"
    else:
        head = f"{{{name}}}"
    return f"{head}({', '.join(args)})"


_ASCII = {"G": "G", "F": "F", "U": " U ", "not": "!", "implies": " -> ", "true": "true"}


def _fmt(ident, latex):
    text = str(ident)
    if latex:
        text = text.replace("\\", r"\textbackslash{}").replace("_", r"\_")
        return rf"\mathit{{{text}}}"
    return text
