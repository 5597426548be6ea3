"""A small general LTL on finite traces: formulas, their parser, the BSI template, the export.

``formula`` holds the tree (:class:`Formula` and its nodes), ``evaluation`` its truth over
ragged traces, ``parser`` :func:`parse_ltl`, ``template`` the reading of a formula as a
:class:`~bsi_sklearn.specification.Specification`; ``ltlf_export`` writes a specification as
LTLf text for Spot, flloat and LTLf2DFA (:func:`to_ltlf`, :class:`SpecificationAutomaton`),
and ``automaton`` builds its minimal DFA itself (:func:`specification_dfa`). The export's
names are imported on first use.
"""

from bsi_sklearn._lazy import lazy_names
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
    "to_ltlf",
    "SpecificationAutomaton",
    "DFA",
    "specification_dfa",
]

_MODULES = {"to_ltlf": "bsi_sklearn.ltl.ltlf_export",
            "SpecificationAutomaton": "bsi_sklearn.ltl.ltlf_export",
            "DFA": "bsi_sklearn.ltl.automaton", "specification_dfa": "bsi_sklearn.ltl.automaton"}

__getattr__, __dir__ = lazy_names("bsi_sklearn.ltl", _MODULES, globals())
