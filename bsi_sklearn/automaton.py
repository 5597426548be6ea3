"""Export of a `Specification`: LTLf text for other tools and a DFA built with flloat.

The template's clauses (``G p``, ``pi -> F w``, ``pi_a -> (!w_b U w_a)``) mean the same on a
finite trace read as it is (LTLf, as flloat and LTLf2DFA read it) and on the infinite trace
whose last state repeats forever (LTL, as Spot reads it, and as this project evaluates
demonstrations): repeating the last state adds no step where ``p`` is false, no first ``w``
and no ``w_b`` before a first ``w_a``. So the same formula text serves both, and the DFA
accepts a trace exactly when :meth:`Specification.satisfied_by` holds.
"""

from __future__ import annotations

import re
from functools import lru_cache

import numpy as np

from bsi_sklearn.param_validation import StrOptions, validate_params

__all__ = ["DIALECTS", "SpecificationAutomaton", "to_ltlf"]

DIALECTS = ("spot", "ltlf2dfa")
_LTLF2DFA_ATOM = re.compile(r"[a-z][a-z0-9_]*\Z")
_SPOT_ATOM = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")
# Words the parsers read as operators or constants, never as atoms.
_RESERVED = {"true", "false", "tt", "ff", "last", "end", "G", "F", "X", "U", "R", "W", "M",
             "WX", "A", "E", "xor"}


def _atom_text(ident, dialect, atoms):
    if atoms is not None and ident in atoms:
        return str(atoms[ident])
    text = str(ident)
    if dialect == "ltlf2dfa":
        if not _LTLF2DFA_ATOM.match(text) or text in _RESERVED:
            raise ValueError(
                f"proposition {ident!r} is not an LTLf2DFA atom (lowercase letters, digits "
                "and underscores, starting with a letter, not a keyword); pass "
                f"atoms={{{ident!r}: 'p0', ...}} to rename it"
            )
        return text
    if _SPOT_ATOM.match(text) and text not in _RESERVED:
        return text
    if '"' in text:
        raise ValueError(f"proposition {ident!r} contains a double quote; rename it with atoms")
    return f'"{text}"'


def to_ltlf(specification, dialect="spot", atoms=None):
    """The specification as formula text for Spot or LTLf2DFA (flloat reads the latter).

    Parameters
    ----------
    specification : Specification
    dialect : {"spot", "ltlf2dfa"}, default="spot"
        ``"spot"`` writes atoms that are not plain identifiers in double quotes;
        ``"ltlf2dfa"`` needs atoms matching ``[a-z][a-z0-9_]*``.
    atoms : mapping, default=None
        Proposition identifier -> atom text, for identifiers the dialect cannot write.

    Returns
    -------
    text : str
        ``true`` for the empty specification.

    Examples
    --------
    >>> from bsi_sklearn import Specification
    >>> spec = Specification(globals=["safe"], eventuals=["a"], orders=[("a", "b")],
    ...                      conditions={"a": "a_ok"})
    >>> to_ltlf(spec)
    'G(safe) & (a_ok -> F(a)) & (a_ok -> (!(b) U (a)))'
    >>> to_ltlf(Specification(globals=[0, "Threat-1"]), dialect="spot")
    'G("0") & G("Threat-1")'
    """
    validate_params({"dialect": dialect}, {"dialect": [StrOptions(DIALECTS)]}, "to_ltlf")
    cond = specification.conditions

    def atom(ident):
        return _atom_text(ident, dialect, atoms)

    def guarded(w, body):
        return f"({atom(cond[w])} -> {body})" if w in cond else body

    parts = [f"G({atom(p)})" for p in sorted(specification.globals, key=_key)]
    parts += [guarded(w, f"F({atom(w)})") for w in sorted(specification.eventuals, key=_key)]
    parts += [guarded(a, f"(!({atom(b)}) U ({atom(a)}))")
              for a, b in sorted(specification.orders, key=lambda p: (_key(p[0]), _key(p[1])))]
    return " & ".join(parts) if parts else "true"


def _key(x):
    return (type(x).__name__, x)


class SpecificationAutomaton:
    """A deterministic finite automaton accepting the traces that satisfy a specification.

    Built with `flloat <https://github.com/whitemech/flloat>`_ (the optional extra
    ``bsi-sklearn[automata]``); usually obtained from :meth:`Specification.to_automaton`.

    Parameters
    ----------
    specification : Specification

    Attributes
    ----------
    specification : Specification
    formula : str
        The LTLf text given to flloat; propositions are renamed ``p0, p1, ...`` (in the order
        of :attr:`propositions`), so any identifiers work.
    propositions : list
        The identifiers the formula mentions.
    dfa : pythomata.SymbolicDFA
        flloat's automaton; its alphabet is the set of assignments of the atoms.

    Examples
    --------
    >>> import numpy as np
    >>> from bsi_sklearn import Specification
    >>> spec = Specification(eventuals=[0, 1], orders=[(0, 1)])
    >>> dfa = spec.to_automaton()
    >>> dfa.accepts(np.array([[1, 0], [1, 1]])), dfa.accepts(np.array([[0, 1], [1, 0]]))
    (True, False)
    """

    def __init__(self, specification):
        self.specification = specification
        spec = specification
        idents = set(spec.globals) | set(spec.eventuals) | {x for o in spec.orders for x in o}
        idents |= set(spec.conditions.values())
        self.propositions = sorted(idents, key=_key)
        self._atoms = {ident: f"p{k}" for k, ident in enumerate(self.propositions)}
        self.formula = to_ltlf(spec, dialect="ltlf2dfa", atoms=self._atoms)
        self.dfa = _build_dfa(self.formula)

    def __repr__(self):
        return (f"SpecificationAutomaton({self.specification.to_ltl()}, "
                f"n_states={len(self.dfa.states)})")

    def accepts(self, trace, feature_names=None):
        """Whether the automaton accepts ``trace`` (read as a finite word, step by step).

        Parameters
        ----------
        trace : array-like of shape (T, n_props) or pandas.DataFrame
            Boolean (or 0/1) trace; columns as for :meth:`Specification.satisfied_by`.
        feature_names : sequence, default=None
            Column names of ``trace``; taken from DataFrame columns when omitted; integer
            identifiers that are not column names are read as column indices.

        Returns
        -------
        accepted : bool
            Equal to ``specification.satisfied_by(trace, feature_names)``.
        """
        from bsi_sklearn.specification import _trace_columns

        columns, arr = _trace_columns(trace, feature_names)
        cols = {}
        for ident in self.propositions:  # the column rule of Specification.satisfied_by
            is_int = isinstance(ident, (int, np.integer))
            if columns is not None and ident in columns:
                cols[ident] = columns[ident]
            elif (columns is None or is_int) and is_int and 0 <= ident < arr.shape[1]:
                cols[ident] = int(ident)
            else:
                raise ValueError(
                    f"proposition {ident!r} is not a column of the trace"
                    + ("" if columns is not None else f" ({arr.shape[1]} columns); pass "
                       "feature_names")
                )
        word = [{self._atoms[i]: bool(row[c]) for i, c in cols.items()} for row in arr]
        return bool(self.dfa.accepts(word))


@lru_cache(maxsize=256)
def _build_dfa(formula):
    try:
        from flloat.parser.ltlf import LTLfParser
    except ImportError:
        raise ImportError(
            "Specification.to_automaton needs flloat: pip install 'bsi-sklearn[automata]' "
            "(or pip install flloat)"
        ) from None
    return LTLfParser()(formula).to_automaton()
