"""Pattern clauses that another clause of the same specification implies.

Under the complexity-based likelihood a MAP holds every clause its acceptable demonstrations
satisfy, so with pattern clauses it often says the same thing several times:
``Absence(refund)`` and ``Response(refund, pay)``, ``Response(refund, ship)``, ... The readable
form leaves out a pattern clause that the other clauses imply together (every finite trace
satisfying them satisfies it: ``F(a) & F(b)`` implies ``CoExistence(a, b)``), as the chain
form leaves out the orders that others imply; the formula means the same.

Each clause is read as a template over its propositions (the paper's clauses too: ``G(p)`` is
``G(x)``, ``pi -> F(w)`` is ``c -> F(x)``, ``pi_a -> (!b U a)`` is ``c -> (!y U x)``), and
clauses imply another when the product of their minimal automata
(:func:`~bsi_sklearn.specification.template_automata.template_dfa`) over the letters of
their propositions reaches no state where they all accept and it rejects. Only the clauses
linked to it through shared propositions can imply it (the others constrain other letters'
bits), so the product is over that group; past :data:`MAX_PROPS` propositions or
:data:`MAX_STATES` product states the clause stays (the check is left, never guessed).
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from bsi_sklearn.specification.template_automata import template_dfa
from bsi_sklearn.specification.templates import TEMPLATES

__all__ = ["implied_patterns", "implies", "MAX_PROPS", "MAX_STATES"]

#: Most propositions (letters: two to the power) of one implication check.
MAX_PROPS = 10
#: Most product states one implication check visits.
MAX_STATES = 20_000


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


def _linked(clauses, props):
    """The clauses linked to ``props`` through chains of shared propositions."""
    reach, linked, rest = set(props), [], list(clauses)
    grew = True
    while grew:
        grew = False
        for c in list(rest):
            if reach.intersection(c[2]):
                reach.update(c[2])
                linked.append(c)
                rest.remove(c)
                grew = True
    return linked


def _conjunction_implies(others, target):
    """Whether the clauses ``others`` together imply ``target``; each ``(template, props)``.

    ``False`` too when the check is too large (:data:`MAX_PROPS`, :data:`MAX_STATES`) or when
    ``others`` are unsatisfiable (then the reader should see every clause).
    """
    clauses = [*others, target]
    union = list(dict.fromkeys(p for _, props in clauses for p in props))
    if len(union) > MAX_PROPS:
        return False
    letters = np.arange(1 << len(union))
    dfas = [template_dfa(t) for t, _ in clauses]
    moves = [d.delta[:, _slot_letters(letters, tuple(union.index(x) for x in props))]
             for d, (_, props) in zip(dfas, clauses)]
    start = tuple(d.start for d in dfas)
    seen, frontier, satisfiable = {start}, [start], False
    while frontier:
        nxt = np.stack([[moves[j][s[j]] for j in range(len(dfas))] for s in frontier])
        nxt = nxt.transpose(0, 2, 1).reshape(-1, len(dfas))  # (states x letters, automata)
        rest_accepts = np.ones(len(nxt), dtype=bool)
        for j, d in enumerate(dfas[:-1]):
            rest_accepts &= d.accepting[nxt[:, j]]
        if (rest_accepts & ~dfas[-1].accepting[nxt[:, -1]]).any():
            return False
        satisfiable |= bool(rest_accepts.any())
        frontier = [s for s in map(tuple, np.unique(nxt, axis=0).tolist()) if s not in seen]
        seen.update(frontier)
        if len(seen) > MAX_STATES:
            return False
    return satisfiable


def implied_patterns(spec):
    """The pattern clauses of ``spec`` that its other clauses imply.

    Clauses are dropped one at a time, the last in rank first (the paper's template before a
    pattern clause, then the catalogue's order), each checked against the clauses still kept:
    of clauses that imply each other, the first is kept, and what stays implies what goes.

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
    >>> spec = Specification(eventuals=["a", "b"], patterns=[("CoExistence", ["a", "b"])])
    >>> sorted(implied_patterns(spec))
    [('P', 'CoExistence', ('a', 'b'))]
    """
    clauses = _clauses(spec)
    order = {name: i for i, name in enumerate(TEMPLATES)}
    rank = {key: (0 if key[0] != "P" else 1, order.get(key[1], len(order)), repr(key))
            for key, _, _ in clauses}
    kept, out = list(clauses), set()
    for clause in sorted((c for c in clauses if c[0][0] == "P"), key=lambda c: rank[c[0]],
                         reverse=True):
        key, t, props = clause
        others = _linked([c for c in kept if c is not clause], props)
        if not others:
            continue
        # one clause alone first: the common case, and cached
        if (any(implies((t2, p2), (t, props)) for _, t2, p2 in others)
                or _conjunction_implies([(t2, p2) for _, t2, p2 in others], (t, props))):
            kept.remove(clause)
            out.add(key)
    return frozenset(out)
