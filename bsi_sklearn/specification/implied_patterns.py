"""Pattern clauses that another clause of the same specification implies.

Under the complexity-based likelihood a MAP holds every clause its acceptable demonstrations
satisfy, so with pattern clauses it often says the same thing several times:
``Absence(refund)`` and ``Response(refund, pay)``, ``Response(refund, ship)``, ... The readable
form leaves out a pattern clause that one other clause implies (every finite trace satisfying
the other satisfies it), as the chain form leaves out the orders that others imply; the
formula means the same.

Each clause is read as a template over its propositions (the paper's clauses too: ``G(p)`` is
``G(x)``, ``pi -> F(w)`` is ``c -> F(x)``, ``pi_a -> (!b U a)`` is ``c -> (!y U x)``), and
one implies another when the product of their minimal automata
(:func:`~bsi_sklearn.specification.template_automata.template_dfa`) over the letters of
their propositions reaches no state where the first accepts and the second rejects. Pairs
only: a clause implied by two others together stays.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from bsi_sklearn.specification.template_automata import template_dfa
from bsi_sklearn.specification.templates import TEMPLATES

__all__ = ["implied_patterns", "implies"]


def _clauses(spec):
    """``(key, template, propositions)`` of every clause of ``spec``, as templates."""
    # A template text's slots are its placeholders in the order they first appear.
    cond = spec.conditions
    out = [(("G", p), "G(x)", (p,)) for p in spec.globals]
    for w in spec.eventuals:
        out.append((("F", w), "c -> F(x)", (cond[w], w)) if w in cond
                   else (("F", w), "F(x)", (w,)))
    for a, b in spec.orders:  # a precedes b: (!b U a)
        out.append((("U", a, b), "c -> (!y U x)", (cond[a], b, a)) if a in cond
                   else (("U", a, b), "!y U x", (b, a)))
    out += [(("P", name, props), name, props) for name, props in spec.patterns]
    return out


def implies(first, second):
    """Whether the clause ``first`` implies ``second``; each ``(template, propositions)``.

    Examples
    --------
    >>> implies(("Absence", ("refund",)), ("Response", ("refund", "pay")))
    True
    >>> implies(("Response", ("refund", "pay")), ("Absence", ("refund",)))
    False
    """
    (t1, p1), (t2, p2) = first, second
    union = list(dict.fromkeys([*p1, *p2]))
    return _implies(t1, tuple(union.index(x) for x in p1), t2,
                    tuple(union.index(x) for x in p2), len(union))


@lru_cache(maxsize=4096)
def _implies(t1, at1, t2, at2, n_props):
    # Breadth-first over the pairs of states the two automata reach on the same traces.
    d1, d2 = template_dfa(t1), template_dfa(t2)
    letters = np.arange(1 << n_props)
    l1 = _slot_letters(letters, at1)
    l2 = _slot_letters(letters, at2)
    seen = {(d1.start, d2.start)}
    stack = [(d1.start, d2.start)]
    while stack:
        s1, s2 = stack.pop()
        for n1, n2 in zip(d1.delta[s1, l1].tolist(), d2.delta[s2, l2].tolist()):
            if (n1, n2) in seen:
                continue
            if d1.accepting[n1] and not d2.accepting[n2]:
                return False
            seen.add((n1, n2))
            stack.append((n1, n2))
    return True


def _slot_letters(letters, at):
    # The template's letter (bit i: slot i holds) of every letter over the propositions.
    out = np.zeros_like(letters)
    for slot, prop in enumerate(at):
        out |= ((letters >> prop) & 1) << slot
    return out


def implied_patterns(spec):
    """The pattern clauses of ``spec`` that one other of its clauses implies.

    Of clauses that imply each other, the first is kept: a clause of the paper's template
    before a pattern clause, then the catalogue's order.

    Returns
    -------
    keys : frozenset of ("P", template, propositions)

    Examples
    --------
    >>> from bsi_sklearn import Specification
    >>> spec = Specification(eventuals=["pay"], patterns=[("Absence", ["refund"]),
    ...                      ("Response", ["refund", "pay"]), ("Existence", ["pay"])])
    >>> sorted(implied_patterns(spec))
    [('P', 'Existence', ('pay',)), ('P', 'Response', ('refund', 'pay'))]
    """
    clauses = _clauses(spec)
    order = {name: i for i, name in enumerate(TEMPLATES)}
    rank = {key: (0 if key[0] != "P" else 1, order.get(key[1], len(order)), repr(key))
            for key, _, _ in clauses}
    out = set()
    for key, t, props in clauses:
        if key[0] != "P":
            continue
        for other, t2, props2 in clauses:
            if other == key or not implies((t2, props2), (t, props)):
                continue
            # equivalent clauses: only the later one goes
            if not implies((t, props), (t2, props2)) or rank[other] < rank[key]:
                out.add(key)
                break
    return frozenset(out)
