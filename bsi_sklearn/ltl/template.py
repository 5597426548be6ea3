"""Reading a formula as the BSI template: the ``Specification`` a formula is equivalent to."""

from __future__ import annotations

from collections.abc import Mapping

from bsi_sklearn.ltl.formula import (
    And,
    Atom,
    Constant,
    Eventually,
    Globally,
    Implies,
    Not,
    Or,
    Until,
)
from bsi_sklearn.ltl.pattern import Pattern
from bsi_sklearn.specification import Specification

__all__ = ["formula_to_specification"]


def _conjuncts(formula):
    if isinstance(formula, And):
        return _conjuncts(formula.left) + _conjuncts(formula.right)
    return [formula]


def _literal(formula, prefix):
    """Proposition name a literal stands for, or None when not a literal."""
    negated = False
    while isinstance(formula, Not):
        negated = not negated
        formula = formula.operand
    if not isinstance(formula, Atom):
        return None
    return prefix + formula.name if negated else formula.name


class _NotInTemplate(Exception):
    pass


def formula_to_specification(formula, names=None, prefix="!"):
    """The :class:`Specification` equivalent to ``formula``, or ``None`` outside the template.

    The reading rules are those of :meth:`Formula.to_specification`, which calls this.

    Parameters
    ----------
    formula : Formula
        The formula.
    names : sequence or mapping, default=None
        Identifiers to use (see :meth:`Formula.to_specification`).
    prefix : str, default="!"
        Prefix naming negated propositions.

    Returns
    -------
    spec : Specification or None

    Examples
    --------
    >>> from bsi_sklearn.ltl import parse_ltl
    >>> formula_to_specification(parse_ltl("G(a) & F(b) & (!c U b)"))
    Specification(globals=['a'], eventuals=['b'], orders=[('b', 'c')])
    """
    globals_, eventuals, orders, patterns = set(), {}, {}, []
    conditions = {}  # subtask -> condition (None: unconditioned)

    def set_condition(w, cond):
        if w in conditions and conditions[w] != cond:
            raise _NotInTemplate
        conditions[w] = cond

    def add_global(body):
        for part in _conjuncts(body):
            if isinstance(part, Globally):
                add_global(part.operand)
            elif isinstance(part, Constant):
                if not part.value:
                    raise _NotInTemplate
            else:
                p = _literal(part, prefix)
                if p is None:
                    raise _NotInTemplate
                globals_.add(p)

    def add_clause(part, cond):
        if isinstance(part, Constant) and part.value:
            return
        if isinstance(part, Eventually):
            if isinstance(part.operand, Constant) and part.operand.value:
                return
            w = _literal(part.operand, prefix)
            if w is None:
                raise _NotInTemplate
            set_condition(w, cond)
            eventuals[w] = cond
            return
        if isinstance(part, Until):
            a = _literal(part.right, prefix)
            if a is None:
                raise _NotInTemplate
            if isinstance(part.left, Constant) and part.left.value:
                b = a
            else:
                b = _literal(Not(part.left), prefix)
                if b is None:
                    raise _NotInTemplate
            set_condition(a, cond)
            if a == b:  # (!a U a) = F(a)
                eventuals[a] = cond
            else:
                orders[(a, b)] = cond
            return
        if cond is None and isinstance(part, Implies):
            pi = _literal(part.left, prefix)
            if pi is None:
                raise _NotInTemplate
            for sub in _conjuncts(part.right):
                add_clause(sub, pi)
            return
        if cond is None and isinstance(part, Or):
            for lit, body in ((part.left, part.right), (part.right, part.left)):
                pi = _literal(Not(lit), prefix)
                if pi is not None and isinstance(body, (Eventually, Until)):
                    add_clause(body, pi)
                    return
        raise _NotInTemplate

    try:
        for part in _conjuncts(formula):
            if isinstance(part, Globally):
                add_global(part.operand)
            elif isinstance(part, Pattern):  # a pattern clause, over literals
                patterns.append((part.template, [_literal(a, prefix) for a in part.args]))
            elif isinstance(part, Constant) and not part.value:
                raise _NotInTemplate
            else:
                add_clause(part, None)
        try:
            closed = Specification(orders=list(orders)).orders
        except ValueError:  # a cycle: a and b must first occur together
            raise _NotInTemplate from None
        # The closure adds (a, c) for a -> b -> c; it is implied only through intermediate
        # subtasks without a condition (their clause holds whatever the trace).
        implied = set()
        succ = {}
        for a, b in orders:
            succ.setdefault(a, set()).add(b)
        for a in succ:
            stack, seen = list(succ[a]), set()
            while stack:
                node = stack.pop()
                if node in seen:
                    continue
                seen.add(node)
                if conditions.get(node) is None:
                    stack.extend(succ.get(node, ()))
            implied.update((a, c) for c in seen)
        if implied != set(closed):
            raise _NotInTemplate
        rename = _renamer(names)
        g = [rename(p) for p in globals_]
        e = [rename(w) for w in eventuals]
        o = [(rename(a), rename(b)) for a, b in orders]
        conds = {rename(w): rename(c) for w, c in conditions.items() if c is not None}
        pats = [(t, [rename(p) for p in props]) for t, props in patterns]
        if any(len(set(props)) < len(props) for _, props in pats):
            raise _NotInTemplate  # Response(a, a): a formula, not a pattern clause
    except _NotInTemplate:
        return None
    return Specification(globals=g, eventuals=e, orders=o, conditions=conds, patterns=pats)


def _renamer(names):
    if names is None:
        return lambda p: p
    if isinstance(names, Mapping):
        def rename(p):
            if p not in names:
                raise _NotInTemplate
            return names[p]
        return rename
    if isinstance(names, str):
        raise ValueError("names must be a sequence or a mapping of proposition names")
    table = {}
    for n in names:
        table.setdefault(n if isinstance(n, str) else str(n), n)
    for n in names:
        if isinstance(n, str):
            table[n] = n

    def rename(p):
        if p not in table:
            raise _NotInTemplate
        return table[p]
    return rename
