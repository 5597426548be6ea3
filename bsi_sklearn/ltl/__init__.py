"""A small general LTL on finite traces: formulas, their parser, and the BSI template.

``formula`` holds the tree (:class:`Formula` and its nodes), ``evaluation`` its truth over
ragged traces, ``parser`` :func:`parse_ltl`, ``template`` the reading of a formula as a
:class:`~bsi_sklearn.specification.Specification`.
"""

from bsi_sklearn.ltl.formula import (
    And,
    Atom,
    Constant,
    Equivalent,
    Eventually,
    Formula,
    Globally,
    Implies,
    Next,
    Not,
    Or,
    Release,
    Until,
)
from bsi_sklearn.ltl.parser import parse_ltl

__all__ = [
    "Formula",
    "Atom",
    "Constant",
    "Not",
    "Next",
    "Eventually",
    "Globally",
    "And",
    "Or",
    "Implies",
    "Equivalent",
    "Until",
    "Release",
    "parse_ltl",
]
