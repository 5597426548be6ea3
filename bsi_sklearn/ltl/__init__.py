"""A small general LTL on finite traces: formulas, their parser, reading one as the template.

``formula`` holds the tree (:class:`Formula` and its nodes; ``pattern`` the pattern-clause node
:class:`Pattern`), ``evaluation`` its truth over
ragged traces, ``parser`` :func:`parse_ltl`, ``template`` the reading of a formula as a
:class:`~bsi_sklearn.specification.Specification`. The other way, a specification written as
LTLf text (:func:`to_ltlf`, :class:`SpecificationAutomaton`) and its minimal DFA
(:func:`specification_dfa`, :class:`DFA`), lives with the value it writes, in
``bsi_sklearn.specification`` (the layer below this one); the names are re-exported here and
imported on first use.
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
from bsi_sklearn.ltl.pattern import Pattern

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
    "Pattern",
    "parse_ltl",
    "to_ltlf",
    "SpecificationAutomaton",
    "DFA",
    "specification_dfa",
]

_MODULES = {"to_ltlf": "bsi_sklearn.specification.ltlf_export",
            "SpecificationAutomaton": "bsi_sklearn.specification.ltlf_export",
            "DFA": "bsi_sklearn.specification.automaton",
            "specification_dfa": "bsi_sklearn.specification.automaton"}

__getattr__, __dir__ = lazy_names("bsi_sklearn.ltl", _MODULES, globals())
