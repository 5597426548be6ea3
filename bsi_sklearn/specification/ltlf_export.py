"""Export of a `Specification`: LTLf text for other tools and its DFA (see ``automaton.py``).

The template's clauses (``G p``, ``pi -> F w``, ``pi_a -> (!w_b U w_a)``) mean the same on a
finite trace read as it is (LTLf, as flloat and LTLf2DFA read it) and on the infinite trace
whose last state repeats forever (LTL, as Spot reads it, and as this project evaluates
demonstrations): repeating the last state adds no step where ``p`` is false, no first ``w``
and no ``w_b`` before a first ``w_a``. So the same formula text serves both, and the DFA (built by
the project, flloat its cross-check in the tests) accepts a trace exactly when
:meth:`Specification.satisfied_by` holds.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from bsi_sklearn._literals import Literal, literal, negation_reader
from bsi_sklearn.data.values import trace_columns
from bsi_sklearn.param_validation import StrOptions, validate_params
from bsi_sklearn.specification._atoms import ltlf_atom_problem, spot_atom
from bsi_sklearn.specification.templates import fill_formula, pattern_order

__all__ = ["DIALECTS", "SpecificationAutomaton", "ltlf_atom_problem", "spot_atom", "to_ltlf"]

DIALECTS = ("spot", "ltlf2dfa")

def _atom_table(idents, dialect, atoms):
    """Identifier -> atom text for every proposition of a formula, checked to be distinct."""
    table = {}
    for ident in idents:
        given = atoms is not None and ident in atoms
        if given:
            text = atoms[ident]
        elif dialect == "ltlf2dfa" and isinstance(ident, (int, np.integer)) \
                and not isinstance(ident, (bool, np.bool_)):
            text = f"p{int(ident)}"  # column indices: flloat atoms cannot start with a digit
        else:
            text = ident
        if dialect == "spot":
            table[ident] = spot_atom(text)
            continue
        problem = ltlf_atom_problem(text)
        if problem is not None:
            source = f"atoms[{ident!r}] = {text!r}" if given else f"proposition {ident!r}"
            raise ValueError(
                f"{source} is not an LTLf2DFA / flloat atom: {problem}; pass "
                f"atoms={{{ident!r}: 'p0', ...}} to rename it"
            )
        table[ident] = str(text)
    seen = {}
    for ident, text in table.items():
        if text in seen:
            raise ValueError(f"propositions {seen[text]!r} and {ident!r} are both written "
                             f"{text!r}; pass atoms= to name them apart")
        seen[text] = ident
    return table


def to_ltlf(specification, dialect="spot", atoms=None, *, negations=None):
    r"""The specification as formula text for Spot or LTLf2DFA (flloat reads the latter).

    Parameters
    ----------
    specification : Specification
    dialect : {"spot", "ltlf2dfa"}, default="spot"
        ``"spot"`` writes in double quotes (a backslash before ``\`` and ``"``) every atom
        Spot would read as something else: a word starting with F, G or X (an operator
        applied to the rest), ``true`` / ``false`` in any case, ``U``, ``R``, ``V``, ``W``,
        ``M``, ``xor``, and anything but letters, digits and underscores.
        ``"ltlf2dfa"`` writes atoms as they are when flloat reads them so
        (``[a-z][a-z0-9_]*``, not starting with ``true``, ``false``, ``last`` or ``end``,
        not ``tt`` / ``ff``), integer propositions (column indices) as ``p0, p1, ...``, and
        raises a ``ValueError`` for any other name: rename it with ``atoms``.
    atoms : mapping, default=None
        Proposition identifier -> atom text, for identifiers the dialect cannot write; the
        same rules apply to the text given. An identifier given here is written as that atom,
        never as a negation.
    negations : None, False or mapping, default=None
        Which propositions are negations of others (see :meth:`Specification.readable`): by
        default a column ``"!q"`` (:class:`~bsi_sklearn.data.preprocessing.NegationAugmenter`,
        :class:`~bsi_sklearn.io.EventLogEncoder`) is written as the negation ``!q`` of the
        atom ``q``, and an order on it, ``(!"!q" U a)``, as ``((q) U (a))``, never ``!!``; a
        mapping ``{negated: proposition}`` (their ``negations_``) names exactly those;
        ``False`` writes every column as an atom of its own (Spot then quotes ``"!q"``,
        LTLf2DFA refuses it).

    Returns
    -------
    text : str
        ``true`` for the empty specification. Parsed by Spot or flloat, it is the same
        formula over the same atoms (over ``q`` for a negated ``"!q"``: on traces where the
        column ``"!q"`` is the negation of ``q``, the formula holds where the specification
        does). A pattern clause is written as its instance's LTLf formula
        (:func:`~bsi_sklearn.specification.templates.instance_ltlf`), in parentheses after
        the other clauses; its ``X`` is LTLf's strong next (``X[!]`` for Spot), so a text with
        pattern clauses is to be read in LTLf (Spot: ``spot.from_ltlf``), not as LTL on the
        repeated last state.

    Raises
    ------
    ValueError
        For a name ``"ltlf2dfa"`` cannot write, or two propositions written alike.

    Examples
    --------
    >>> from bsi_sklearn import Specification
    >>> spec = Specification(globals=["safe"], eventuals=["a"], orders=[("a", "b")],
    ...                      conditions={"a": "a_ok"})
    >>> to_ltlf(spec)
    'G(safe) & (a_ok -> F(a)) & (a_ok -> (!(b) U (a)))'
    >>> to_ltlf(Specification(globals=[0, "Threat-1", "Fuel"]), dialect="spot")
    'G("0") & G("Fuel") & G("Threat-1")'
    >>> to_ltlf(Specification(globals=[0], eventuals=[1, 2]), dialect="ltlf2dfa")
    'G(p0) & F(p1) & F(p2)'
    >>> to_ltlf(Specification(globals=["!r"], orders=[("a", "!q")]), dialect="ltlf2dfa")
    'G(!r) & ((q) U (a))'
    >>> to_ltlf(Specification(globals=["s"], patterns=[("ChainResponse", ["!a", "b"])]))
    'G(s) & (G((!a) -> X[!](b)))'
    """
    validate_params({"dialect": dialect}, {"dialect": [StrOptions(DIALECTS)]}, "to_ltlf")
    if atoms is not None and not isinstance(atoms, Mapping):
        raise ValueError(f"to_ltlf: atoms must be a mapping identifier -> atom text, got "
                         f"{type(atoms).__name__}")
    negates = negation_reader(negations, "to_ltlf")

    def lit(ident):
        if atoms is not None and ident in atoms:
            return Literal(ident)
        return literal(ident, negates)

    cond = specification.conditions
    literals = {ident: lit(ident) for ident in _propositions(specification)}
    table = _atom_table(sorted({x.atom for x in literals.values()}, key=_key), dialect, atoms)

    def text(ident):
        x = literals[ident]
        return table[x.atom] if x.positive else f"!{table[x.atom]}"

    def guarded(w, body):
        return f"({text(cond[w])} -> {body})" if w in cond else body

    def until(a, b):
        x = literals[b]  # !b, without a double negation
        left = f"!({table[x.atom]})" if x.positive else f"({table[x.atom]})"
        return f"({left} U ({text(a)}))"

    parts = [f"G({text(p)})" for p in sorted(specification.globals, key=_key)]
    parts += [guarded(w, f"F({text(w)})") for w in sorted(specification.eventuals, key=_key)]
    parts += [guarded(a, until(a, b))
              for a, b in sorted(specification.orders, key=lambda p: (_key(p[0]), _key(p[1])))]
    # A pattern clause is its instance's LTLf formula (a negated column its literal, in
    # parentheses where the template's atom stood).
    parts += [f"({fill_formula(name, [_atom_text(literals[p], table) for p in props], dialect)})"
              for name, props in sorted(specification.patterns, key=pattern_order)]
    return " & ".join(parts) if parts else "true"


def _key(x):
    return (type(x).__name__, x)


def _propositions(spec):
    """Every proposition a specification mentions: its clauses', conditions and patterns'."""
    return (set(spec.globals) | set(spec.eventuals) | {x for o in spec.orders for x in o}
            | set(spec.conditions.values()) | {x for _, props in spec.patterns for x in props})


def _atom_text(lit, table):
    return table[lit.atom] if lit.positive else f"(!{table[lit.atom]})"


class SpecificationAutomaton:
    """A deterministic finite automaton accepting the traces that satisfy a specification.

    Built by the project (:mod:`bsi_sklearn.specification.automaton`): each clause is a small
    automaton and the specification's is their product, minimised; usually obtained from
    :meth:`Specification.to_automaton`. No optional package is needed; flloat, given
    :attr:`formula`, builds the same language (the tests check it).

    Parameters
    ----------
    specification : Specification

    Attributes
    ----------
    specification : Specification
    formula : str
        The formula as LTLf2DFA / flloat text, propositions renamed ``p0, p1, ...`` (in the
        order of :attr:`propositions`), so any identifiers work.
    propositions : list
        The identifiers the formula mentions.
    dfa : bsi_sklearn.specification.automaton.DFA
        The minimal automaton: ``dfa.n_states``, ``dfa.delta``, ``dfa.accepting``,
        ``dfa.to_dot()``, ``dfa.to_hoa()``.

    Examples
    --------
    >>> import numpy as np
    >>> from bsi_sklearn import Specification
    >>> spec = Specification(eventuals=[0, 1], orders=[(0, 1)])
    >>> dfa = spec.to_automaton()
    >>> dfa.accepts(np.array([[1, 0], [1, 1]])), dfa.accepts(np.array([[0, 1], [1, 0]]))
    (True, False)
    >>> dfa.dfa.n_states
    4
    """

    def __init__(self, specification):
        from bsi_sklearn.specification.automaton import specification_dfa

        self.specification = specification
        spec = specification
        self.propositions = sorted(_propositions(spec), key=_key)
        self._atoms = {ident: f"p{k}" for k, ident in enumerate(self.propositions)}
        self.formula = to_ltlf(spec, dialect="ltlf2dfa", atoms=self._atoms, negations=False)
        self.dfa = specification_dfa(spec)

    def __repr__(self):
        return (f"SpecificationAutomaton({self.specification.to_ltl()}, "
                f"n_states={self.dfa.n_states})")

    def to_dot(self):
        """The automaton in Graphviz DOT (accepting states doubled, edges labelled)."""
        return self.dfa.to_dot(name=self.specification.to_ltl())

    def to_hoa(self):
        """The automaton in the HOA v1 format (:meth:`.automaton.DFA.to_hoa`).

        The propositions are the ``AP:``, edges have explicit labels, accepting states are in
        acceptance set 0; the automaton is read over finite words.
        """
        return self.dfa.to_hoa(name=self.specification.to_ltl())

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
        columns, arr = trace_columns(trace, feature_names)
        cols = {}
        for ident in self.propositions:  # the column rule of Specification.satisfied_by
            is_int = isinstance(ident, (int, np.integer))
            if columns is not None and ident in columns:
                cols[ident] = arr[:, columns[ident]]
            elif (columns is None or is_int) and is_int and 0 <= ident < arr.shape[1]:
                cols[ident] = arr[:, int(ident)]
            else:
                raise ValueError(
                    f"proposition {ident!r} is not a column of the trace"
                    + ("" if columns is not None else f" ({arr.shape[1]} columns); pass "
                       "feature_names")
                )
        state = self.dfa.run(self.dfa.letters(cols, arr.shape[0]))
        return bool(self.dfa.accepting[state])
