"""Negated propositions in rendered formulas: which column negates which, clauses over literals.

:class:`~bsi_sklearn.data.preprocessing.NegationAugmenter` (default ``prefix="!"``) and
:class:`~bsi_sklearn.io.EventLogEncoder` (``negations=True``) name the negation of a column
``p`` ``"!p"``, and :meth:`bsi_sklearn.ltl.Formula.to_specification` names a negated literal
so; the readable renderings (``Specification.readable``, ``unicode_ltl``, the sentences of
``report.wording``) and ``to_ltlf`` read such a column as the literal *not p*. Which columns
are negations is the ``negations`` argument they all take:

- ``None`` (default): the naming convention above, a string ``"!" + p`` (``p`` not empty) is
  the negation of ``p`` (so ``"!!p"`` is ``p``);
- a mapping ``{negated column: the column it negates}``, exactly those (what
  ``NegationAugmenter.negations_`` and ``EventLogEncoder.negations_`` give, for any prefix);
  any other identifier is an atom, even one whose name starts with ``!``;
- ``False``: none, every identifier an atom.

A clause is then a formula over literals, and :func:`clause_form` writes it without double
negations and, with ``simplify=True``, with the order clauses that relate a proposition to its
own negation reduced (each rule holds for every finite trace on which the negated column is
the negation; ``tests/test_readable_negations.py`` checks them all by brute force, against the
project's clause truth too):

=====================================  ======================  =============================
clause over columns                    literals                written
=====================================  ======================  =============================
order ``(p, "!p")``                    ``(!!p U p)``           ``p`` (p at the first step)
order ``("!p", p)``                    ``(!p U !p)``           ``!p``
order ``(a, b)``, ``b`` names ``a``    ``(!a U a)``            ``F(a)``
order ``(a, "!q")``                    ``(!!q U a)``           ``(q U a)``
``pi_w -> ...`` with ``pi_w = !w``     ``(!w -> F(w))``        ``F(w)`` (the condition goes)
``pi_w -> ...`` with ``pi_w`` = ``w``  ``(w -> F(w))``         ``true``
=====================================  ======================  =============================
"""

from __future__ import annotations

from collections.abc import Hashable, Mapping
from typing import NamedTuple

__all__ = ["Literal", "clause_form", "literal", "negation_reader", "readable_atom",
           "render_clause"]


class Literal(NamedTuple):
    """A proposition that is not a negation, and whether it is taken as is or negated."""

    atom: Hashable
    positive: bool = True

    def negated(self):
        return Literal(self.atom, not self.positive)


def _by_name(ident):
    if isinstance(ident, str) and len(ident) > 1 and ident[0] == "!":
        return ident[1:]
    return None


def _none(ident):
    return None


def negation_reader(negations, caller="negations"):
    """``ident -> the identifier it negates`` (``None`` when it is no negation).

    ``negations`` is ``None`` (the ``"!p"`` naming convention), ``False`` (no negations) or a
    mapping negated column -> the column it negates; see the module docstring.
    """
    if negations is None or negations is True:
        return _by_name
    if negations is False:
        return _none
    if not isinstance(negations, Mapping):
        raise ValueError(
            f"{caller}: negations must be None (a column '!p' negates p), False (no "
            f"negations) or a mapping negated column -> the column it negates, got "
            f"{type(negations).__name__}"
        )
    table = {}
    for neg, pos in negations.items():
        if not isinstance(pos, Hashable) or neg == pos:
            raise ValueError(f"{caller}: negations[{neg!r}] = {pos!r} is not another column")
        table[neg] = pos

    def read(ident):
        try:
            return table.get(ident)
        except TypeError:  # an unhashable identifier is never a key
            return None
    return read


def literal(ident, negates):
    """The :class:`Literal` a column stands for, through chains of negations."""
    positive, seen = True, [ident]
    while True:
        base = negates(ident)
        if base is None:
            return Literal(ident, positive)
        if base in seen:
            raise ValueError(f"negations: {seen[0]!r} negates itself through {seen[1:]!r}")
        seen.append(base)
        ident, positive = base, not positive


def clause_form(key, conditions, negates, *, simplify=True):
    """A clause key as ``(condition literal or None, body)`` over literals.

    ``body`` is ``("G", L)``, ``("F", L)``, ``("U", left, right)`` (``left U right``),
    ``("now", L)`` (``L`` at the first step) or ``("true",)``; the last two only with
    ``simplify=True``, which applies the table of the module docstring. Without it the clause
    keeps its shape and only its literals lose their double negations (for export).
    """
    kind = key[0]
    if kind == "G":
        return None, ("G", literal(key[1], negates))
    target = literal(key[1], negates)
    if kind == "F":
        body = ("F", target)
    else:
        b = literal(key[2], negates)
        if simplify and b == target.negated():
            body = ("now", target)   # (a U a) = a
        elif simplify and b == target:
            body = ("F", target)     # (!a U a) = F(a)
        else:
            body = ("U", b.negated(), target)
    cond = conditions.get(key[1]) if conditions else None
    if cond is None:
        return None, body
    c = literal(cond, negates)
    if simplify and c == target:
        return None, ("true",)     # the condition makes the clause hold at the first step
    if simplify and c == target.negated():
        return None, body          # the clause holds where the condition is false
    return c, body


def readable_atom(ident):
    """A proposition in the readable texts: its name, in quotes when it starts with ``!``.

    Such a name is no negation there (:func:`literal` took negations apart), and quoted it
    reads back with :func:`bsi_sklearn.ltl.parse_ltl` as that atom.
    """
    text = str(ident)
    return f'"{text}"' if text.startswith("!") and '"' not in text else text


def render_clause(form, atom, symbols):
    """The text of a :func:`clause_form`.

    ``atom(ident)`` writes a proposition; ``symbols`` maps ``"G" "F" "U" "not" "implies"
    "true"`` to the operators (``"U"`` and ``"implies"`` with their spaces).
    """
    def lit(x):
        return atom(x.atom) if x.positive else f"{symbols['not']}{atom(x.atom)}"

    cond, body = form
    kind = body[0]
    if kind == "true":
        return symbols["true"]
    if kind in ("G", "F"):
        text = f"{symbols[kind]}({lit(body[1])})"
    elif kind == "now":
        text = lit(body[1])
    else:
        text = f"({lit(body[1])}{symbols['U']}{lit(body[2])})"
    return text if cond is None else f"({lit(cond)}{symbols['implies']}{text})"
