"""The pattern-clause node of a formula: a template over literals, read in LTLf (DESIGN §12)."""

from __future__ import annotations

import re
from dataclasses import dataclass

import numpy as np

from bsi_sklearn.ltl.formula import Atom, Formula, Not
from bsi_sklearn.specification.template_truth import step_truth
from bsi_sklearn.specification.templates import TEMPLATES, get_template

__all__ = ["Pattern"]


@dataclass(frozen=True, repr=False)
class Pattern(Formula):
    """A pattern clause: a template (DESIGN §12) over literals, read in LTLf.

    Written ``Response(a, b)`` for a template of the catalogue
    (:data:`bsi_sklearn.specification.templates.TEMPLATES`) and ``{G(x -> WX(!x))}(a)``
    for a user template (its LTLf text in braces), as :meth:`Specification.to_ltl` writes a
    pattern clause. Unlike the other nodes, the template is read in LTLf on the finite trace
    as it is (its ``X`` is false at the last step, ``WX`` true): at step ``t`` it is the
    template's truth on the steps from ``t`` to the end, and at the repeated last state its
    truth there.

    Parameters
    ----------
    template : str
        A catalogue name or the LTLf text of a user template.
    args : tuple of Formula
        The propositions filling the template's slots, in slot order: atoms or negated atoms.

    Raises
    ------
    ValueError
        For an unknown template name (the known ones listed), a number of arguments other
        than the template's slots, or an argument that is not a literal.

    Examples
    --------
    >>> import numpy as np
    >>> from bsi_sklearn.ltl import parse_ltl
    >>> phi = parse_ltl("ChainResponse(a, b) & G(!c)")
    >>> phi.satisfied_by(np.array([[1, 0, 0], [0, 1, 0]]), feature_names=["a", "b", "c"])
    True
    >>> phi.satisfied_by(np.array([[0, 1, 0], [1, 0, 0]]), feature_names=["a", "b", "c"])
    False
    >>> print(phi.to_specification())
    G(!c) & ChainResponse(a, b)
    """

    template: str
    args: tuple

    def __post_init__(self):
        name = self.template.strip() if isinstance(self.template, str) else self.template
        if isinstance(name, str) and name not in TEMPLATES and \
                re.fullmatch(r"[A-Za-z_][A-Za-z0-9_.]*", name) and name[0].islower():
            raise ValueError(f"unknown template {name!r}; the known templates are: "
                             f"{', '.join(TEMPLATES)}; a user template is written as its LTLf "
                             "text in braces, such as {G(x -> F(y))}(a, b)")
        t = get_template(name)
        args = tuple(self.args)
        for arg in args:
            if not _is_literal(arg):
                raise ValueError(f"the template {t.name!r} takes propositions or their "
                                 f"negations, got {arg}")
        if len(args) != len(t.slots):
            raise ValueError(f"the template {t.name!r} has {len(t.slots)} slots "
                             f"({', '.join(t.slots)}), got {len(args)} arguments")
        object.__setattr__(self, "template", t.name)
        object.__setattr__(self, "args", args)

    @property
    def children(self):
        """The arguments, in slot order."""
        return self.args

    def _head(self):
        return self.template if self.template in TEMPLATES else f"{{{self.template}}}"

    def to_prefix(self):
        """Render in prefix notation: ``Response(a,b)``."""
        return f"{self._head()}({','.join(a.to_prefix() for a in self.args)})"

    def _infix(self, top=False):
        return f"{self._head()}({', '.join(a._infix(top=True) for a in self.args)})"

    def _compute(self, cube, columns, cache):
        values = np.stack([a._eval(cube, columns, cache) for a in self.args], axis=-1)
        # evaluate_traces leaves each padded trace's length here: LTLf needs its end.
        return step_truth(self.template, values, cache.get("lengths"))


def _is_literal(formula):
    while isinstance(formula, Not):
        formula = formula.operand
    return isinstance(formula, Atom)
