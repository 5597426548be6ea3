"""Clause wording: clause keys in reading order, one-clause specifications, English sentences."""

from __future__ import annotations

from collections.abc import Mapping

from bsi_sklearn._literals import (
    clause_form,
    literal,
    negation_reader,
    readable_atom,
    render_clause,
)
from bsi_sklearn.specification import Specification
from bsi_sklearn.specification.templates import instance_text, pattern_order

__all__ = [
    "clause_sentence",
    "event_log_sentence",
    "describe_event_log_specification",
    "clause_specification",
    "describe_specification",
    "ordered_clauses",
    "unicode_ltl",
    "violated_clauses",
]

_KINDS = {"G": "global", "F": "eventual", "U": "order", "P": "pattern"}
_ASCII = {"G": "G", "F": "F", "U": " U ", "not": "!", "implies": " -> ", "true": "true"}
_UNICODE = {"G": "□", "F": "◇", "U": " U ", "not": "¬", "implies": " → ", "true": "⊤"}


def _sort_key(x):
    return (type(x).__name__, x)


def ordered_clauses(specification):
    """Clause keys of a specification in reading order: globals, eventuals, orders, patterns.

    Keys are ``("G", p)``, ``("F", w)``, ``("U", a, b)`` (*a precedes b*) and
    ``("P", template, propositions)``, as in
    :meth:`Specification.clauses`; within a kind they are sorted by identifier, the order
    of :meth:`Specification.clause_strings`.

    Examples
    --------
    >>> from bsi_sklearn import Specification
    >>> ordered_clauses(Specification(globals=["safe"], eventuals=["b", "a"],
    ...                               orders=[("a", "b")]))
    [('G', 'safe'), ('F', 'a'), ('F', 'b'), ('U', 'a', 'b')]
    """
    spec = _check_spec(specification)
    return (
        [("G", p) for p in sorted(spec.globals, key=_sort_key)]
        + [("F", w) for w in sorted(spec.eventuals, key=_sort_key)]
        + [("U", a, b) for a, b in sorted(spec.orders,
                                          key=lambda o: (_sort_key(o[0]), _sort_key(o[1])))]
        # the pattern clauses last, catalogue templates first, as clause_strings lists them
        + [("P", t, ps) for t, ps in sorted(spec.patterns, key=pattern_order)]
    )


def unicode_ltl(specification, *, chains=False, vacuous=(), negations=None):
    """The specification in temporal-logic symbols, as plain Unicode text.

    ``□`` is *always* (G), ``◇`` *eventually* (F), ``U`` *until*, ``¬`` *not*, ``→``
    *implies*, ``∧`` *and*; the empty specification is ``⊤``. Reports show formulas this way:
    readable in any viewer, with no LaTeX and nothing fetched from the network.

    Parameters
    ----------
    specification : Specification
    chains : bool, default=False
        Leave out the orders the others imply (:meth:`Specification.implied_orders`).
    vacuous : iterable of clause keys, default=()
        Clauses set apart after the formula, as ``[untested: ...]`` (see
        :meth:`Specification.readable`).
    negations : None, False or mapping, default=None
        Which propositions negate others, as for :meth:`Specification.readable`: by default
        ``"!q"`` is ``¬q``, never ``¬!q``, and an order between a proposition and its own
        negation is written as the simpler formula it equals (``(¬!p U p)`` as ``p``).

    Returns
    -------
    text : str

    Examples
    --------
    >>> from bsi_sklearn import Specification
    >>> spec = Specification(globals=["safe"], eventuals=["a", "b"], orders=[("a", "b")],
    ...                      conditions={"a": "a_ok"})
    >>> print(unicode_ltl(spec))
    □(safe) ∧ (a_ok → ◇(a)) ∧ ◇(b) ∧ (a_ok → (¬b U a))
    >>> unicode_ltl(Specification())
    '⊤'
    >>> chain = Specification(orders=[("a", "b"), ("b", "c")])
    >>> print(unicode_ltl(chain, chains=True, vacuous=[("U", "a", "b")]))
    (¬c U b)  [untested: (¬b U a)]
    >>> print(unicode_ltl(Specification(globals=["!r"], orders=[("a", "!p"), ("!q", "q")])))
    □(¬r) ∧ ¬q ∧ (p U a)
    """
    spec = _check_spec(specification)
    negates = negation_reader(negations, "unicode_ltl")
    cond = spec.conditions
    implied = spec.implied_clauses() if chains else frozenset()
    vacuous = set(vacuous)
    parts, apart = [], []
    for key in ordered_clauses(spec):
        if key in implied:
            continue
        if key[0] == "P":  # written by its template's name, as readable() writes it
            text = clause_specification(key).readable(negations=negations)
        else:
            text = render_clause(clause_form(key, cond, negates), readable_atom, _UNICODE)
        (apart if key in vacuous else parts).append(text)
    shown = " ∧ ".join(parts) if parts else "⊤"
    return f"{shown}  [untested: {' ∧ '.join(apart)}]" if apart else shown


def clause_specification(clause, conditions=None):
    """The one-clause :class:`Specification` of a clause key.

    Parameters
    ----------
    clause : tuple
        ``("G", p)``, ``("F", w)`` or ``("U", a, b)``.
    conditions : mapping, default=None
        Subtask -> condition proposition, as in :class:`Specification`.

    Returns
    -------
    Specification

    Examples
    --------
    >>> print(clause_specification(("U", "a", "b"), {"a": "a_ok"}).to_ltl())
    (a_ok -> (!b U a))
    """
    kind = _check_clause(clause)
    if kind == "P":
        return Specification(patterns=[(clause[1], clause[2])])
    if kind == "G":
        return Specification(globals=[clause[1]])
    if kind == "F":
        return Specification(eventuals=[clause[1]], conditions=conditions)
    return Specification(orders=[(clause[1], clause[2])], conditions=conditions)


def _check_clause(clause):
    ok = isinstance(clause, tuple) and len(clause) >= 2 and clause[0] in _KINDS and (
        len(clause) == (3 if clause[0] in ("U", "P") else 2)) and (
        clause[0] != "P" or isinstance(clause[2], tuple))
    if not ok:
        raise ValueError(
            f"clause {clause!r} is not a clause key ('G', p), ('F', w), ('U', a, b) or "
            "('P', template, propositions)"
        )
    return clause[0]


def _check_descriptions(descriptions, names=None):
    if descriptions is None:
        return {}
    if not isinstance(descriptions, Mapping):
        raise ValueError(
            f"descriptions must be a mapping proposition -> phrase, got "
            f"{type(descriptions).__name__}"
        )
    for key, text in descriptions.items():
        if not isinstance(text, str) or not text.strip():
            raise ValueError(f"descriptions[{key!r}] must be a non-empty string, got {text!r}")
        if names is not None and key not in names:
            raise ValueError(
                f"descriptions: {key!r} is not a proposition of the classifier; known "
                f"propositions are {list(names)[:20]}{' ...' if len(names) > 20 else ''}"
            )
    return {k: " ".join(v.split()) for k, v in descriptions.items()}


def _phrase(ident, descriptions):
    return descriptions[ident] if ident in descriptions else f"{ident} holds"


def _capitalised(ident, descriptions):
    text = _phrase(ident, descriptions)
    if ident in descriptions and text[:1].islower():
        text = text[0].upper() + text[1:]
    return text


def _said(lit, d, column=None):
    """The phrase of a literal, ``(text, described)``: the column's own description first."""
    if column is not None and column in d:
        return d[column], True
    if lit.positive:
        return _phrase(lit.atom, d), lit.atom in d
    if lit.atom in d:
        return f"it is not the case that {d[lit.atom]}", True
    return f"{lit.atom} does not hold", False


def _upper(said):
    text, described = said
    return text[0].upper() + text[1:] if described and text[:1].islower() else text


def _form(clause, cond, negates):
    # A clause the condition makes true at once is said as it is ("If w holds, eventually w
    # holds."): a sentence for "true" would hide what the formula has.
    form = clause_form(clause, cond, negates)
    return form if form[1] != ("true",) else clause_form(clause, cond, negates, simplify=False)


def clause_sentence(clause, conditions=None, descriptions=None, *, negations=None):
    """One plain-English sentence for a clause.

    Every proposition is read through its phrase: ``descriptions[p]`` when given (a short
    statement in the present tense, e.g. ``"POI 3 is visited"``), else ``"p holds"``. With
    phrases ``P``, ``W``, ``A``, ``B`` and condition phrases ``C``:

    ==========================  =============================================
    clause                      sentence
    ==========================  =============================================
    ``G(p)``                    ``Always, P.``
    ``F(w)``                    ``Eventually, W.``
    ``pi_w -> F(w)``            ``If C, eventually W.``
    ``!b U a``                  ``A before B.`` (first letter capitalised)
    ``pi_a -> (!b U a)``        ``If C, A before B.``
    ``G(!q)``                   ``q never holds.`` (``Never, Q.`` when ``q`` is described)
    ``q U a`` (order on ``!q``) ``Q until A.``
    ``p`` (``(!!p U p)``)       ``P at the first step.``
    ==========================  =============================================

    "A before B" is the strong until of the template: A does happen, and B does not happen
    at an earlier step than A (both at the same step is fine); "Q until A" likewise: A does
    happen, and Q holds at every earlier step. Conditions are read at the first step of a
    demonstration.

    A negation ``!q`` (see ``negations``) reads "not q": ``descriptions["!q"]`` when given,
    else ``"q does not hold"``, or ``"it is not the case that Q"`` when ``q`` is described;
    never "!q holds" nor a double negation. Orders between a proposition and its own negation
    are said as the simpler clause they equal (:meth:`Specification.readable`).

    Parameters
    ----------
    clause : tuple
        ``("G", p)``, ``("F", w)`` or ``("U", a, b)``.
    conditions : mapping, default=None
        Subtask -> condition proposition.
    descriptions : mapping, default=None
        Proposition -> short phrase.
    negations : None, False or mapping, default=None
        Which propositions negate others: by default ``"!q"`` negates ``q``; a mapping
        ``{negated: proposition}`` names exactly those; ``False`` none (see
        :meth:`Specification.readable`).

    Returns
    -------
    str

    Examples
    --------
    >>> d = {"alive": "the strikers are alive", "omega_3": "POI 3 is visited",
    ...      "pi_3": "POI 3 is accessible", "omega_1": "POI 1 is visited",
    ...      "pi_1": "POI 1 is accessible"}
    >>> clause_sentence(("G", "alive"), descriptions=d)
    'Always, the strikers are alive.'
    >>> clause_sentence(("F", "omega_3"), {"omega_3": "pi_3"}, d)
    'If POI 3 is accessible, eventually POI 3 is visited.'
    >>> clause_sentence(("U", "omega_1", "omega_3"), descriptions=d)
    'POI 1 is visited before POI 3 is visited.'
    >>> clause_sentence(("F", "omega_2"))
    'Eventually, omega_2 holds.'
    >>> clause_sentence(("G", "!q")), clause_sentence(("F", "!q"))
    ('q never holds.', 'Eventually, q does not hold.')
    >>> clause_sentence(("U", "omega_1", "!pi_1"), descriptions=d)
    'POI 1 is accessible until POI 1 is visited.'
    >>> clause_sentence(("P", "Response", ("order", "pay")))
    'Response(order, pay): every order is eventually followed by pay.'
    """
    if _check_clause(clause) == "P":
        return _pattern_sentence(clause)
    d = _check_descriptions(descriptions)
    cond = dict(conditions) if conditions is not None else {}
    negates = negation_reader(negations, "clause_sentence")
    c, body = _form(clause, {k: v for k, v in cond.items() if v is not None}, negates)
    kind, subject = body[0], clause[1]
    if kind == "G":
        lit = body[1]
        if lit.positive or subject in d:
            return f"Always, {_said(lit, d, subject)[0]}."
        return f"Never, {d[lit.atom]}." if lit.atom in d else f"{lit.atom} never holds."
    said = _said(body[-1], d, subject)  # the subtask (the right of U)
    first = said  # the phrase that opens the sentence
    if kind == "F":
        if c is None:
            return f"Eventually, {said[0]}."
        text = f"eventually {said[0]}."
    elif kind == "now":
        text = f"{said[0]} at the first step."
    elif body[1].positive:  # q U a: an order on a negated b
        first = _said(body[1], d)
        text = f"{first[0]} until {said[0]}."
    else:
        text = f"{said[0]} before {_said(literal(clause[2], negates), d, clause[2])[0]}."
    if c is not None:
        return f"If {_said(c, d, cond[subject])[0]}, {text}"
    return _upper((text, first[1]))


def event_log_sentence(clause, conditions=None, *, negations=None, repeats=None):
    """One sentence for a clause over event-log propositions, with its Declare name.

    Under :class:`bsi_sklearn.io.EventLogEncoder`'s default encoding a proposition ``a`` reads
    "activity a has occurred so far" (false at the first step), its negation ``!a`` "a has
    not occurred yet" (true at the first step), so the template's clauses are Declare
    constraints on the case:

    ==========================  =====================================================
    clause                      sentence
    ==========================  =====================================================
    ``F(a)``                    ``existence(a): a occurs.``
    ``!b U a``                  ``existence(a) and precedence(a, b): a occurs, and
                                no b before the first a.``
    ``G(!a)``                   ``absence(a): a never occurs.`` (``!a`` is the
                                negated column of ``EventLogEncoder(negations=True)``)
    ``G(p)``                    ``p has occurred from the start`` (never true of an
                                encoded case: its first step is empty)
    ==========================  =====================================================

    The other clauses on negated columns hold in every case or in none, as the sentence
    says: ``F(!a)``, and an order whose subtask is ``!a``, in every case (a has not occurred at
    its start); an order on ``!b`` (``b U a``) in none. ``negations`` says which propositions
    are negations (by default ``"!a"`` negates ``a``; see :meth:`Specification.readable`).

    A condition ``pi`` (read at the first step, where nothing has occurred yet) is said as
    "if pi has occurred at the start".

    ``repeats`` (``EventLogEncoder.repeats_``, ``{"pay<=1": "pay"}``) names the at-most-once
    columns: ``G(pay<=1)`` is ``absence2(pay): pay occurs at most once.`` (default: none).

    Examples
    --------
    >>> event_log_sentence(("F", "pay"))
    'existence(pay): pay occurs.'
    >>> event_log_sentence(("U", "pay", "ship"))
    'existence(pay) and precedence(pay, ship): pay occurs, and no ship before the first pay.'
    >>> event_log_sentence(("G", "!refund"))
    'absence(refund): refund never occurs.'
    >>> event_log_sentence(("F", "!refund"))
    'refund has not occurred at some step: true of every case (at its start).'
    >>> event_log_sentence(("G", "pay<=1"), repeats={"pay<=1": "pay"})
    'absence2(pay): pay occurs at most once.'
    """
    if _check_clause(clause) == "P":
        return _pattern_sentence(clause)
    cond = {k: v for k, v in (conditions or {}).items() if v is not None}
    negates = negation_reader(negations, "event_log_sentence")
    c, body = _form(clause, cond, negates)
    kind, lit = body[0], body[-1]
    a, b = lit.atom, (repeats or {}).get(lit.atom)  # b: a is "b occurred at most once so far"
    none = "true of no case (nothing has occurred at its start)"
    if lit.positive and b is not None and kind in ("G", "F", "now"):
        text = (f"absence2({b}): {b} occurs at most once." if kind == "G" else
                f"{b} has occurred at most once so far: true of every case at its start.")
    elif kind == "G":
        text = (f"{a} has occurred from the start." if lit.positive
                else f"absence({a}): {a} never occurs.")
    elif kind == "F":
        text = f"existence({a}): {a} occurs." if lit.positive else \
            f"{a} has not occurred at some step: true of every case (at its start)."
    elif kind == "now":
        text = (f"{a} has occurred at the start: {none}." if lit.positive
                else f"{a} has not occurred at the start: true of every case.")
    elif not lit.positive:
        text = (f"{render_clause((None, body), readable_atom, _ASCII)}: true of every case "
                f"({a} has not occurred at its start).")
    elif body[1].positive:  # q U a
        text = f"{body[1].atom} has occurred from the start until {a} occurs: {none}."
    else:
        b = body[1].atom
        text = (f"existence({a}) and precedence({a}, {b}): {a} occurs, and no {b} before "
                f"the first {a}.")
    if c is not None:
        text = f"If {c.atom} has {'' if c.positive else 'not '}occurred at the start, {text}"
    return text


def describe_event_log_specification(specification, vacuous=(), *, chains=True,
                                     negations=None, repeats=None):
    """:func:`event_log_sentence` for every clause, in :func:`ordered_clauses` order.

    Clauses in ``vacuous`` (``BSIClassifier.vacuous_clauses_``: untested by the data) are
    left out; ``chains=True`` (the default) leaves out the orders the others imply;
    ``negations`` (``EventLogEncoder.negations_``, by default every ``"!a"``) and
    ``repeats`` (``EventLogEncoder.repeats_``) as for :func:`event_log_sentence`.

    Examples
    --------
    >>> from bsi_sklearn import Specification
    >>> spec = Specification(eventuals=["order"], orders=[("order", "pay"), ("pay", "ship"),
    ...                                                   ("order", "ship")])
    >>> for line in describe_event_log_specification(spec):
    ...     print(line)
    existence(order): order occurs.
    existence(order) and precedence(order, pay): order occurs, and no pay before the first order.
    existence(pay) and precedence(pay, ship): pay occurs, and no ship before the first pay.
    """
    return _sentences(specification,
                      lambda clause, conditions: event_log_sentence(
                          clause, conditions, negations=negations, repeats=repeats),
                      chains, vacuous)


def _sentences(specification, sentence, chains, skip=()):
    # sentence(clause, conditions) of every clause in reading order, but those in skip and,
    # with chains, the clauses the others imply (Specification.implied_clauses).
    spec = _check_spec(specification)
    leave = {tuple(c) for c in skip}
    if chains:
        leave |= spec.implied_clauses()
    return [sentence(c, spec.conditions) for c in ordered_clauses(spec) if c not in leave]


def describe_specification(specification, descriptions=None, *, chains=False,
                           negations=None):
    """One sentence per clause of a specification, in :func:`ordered_clauses` order.

    See :func:`clause_sentence` for the phrasing (and ``negations``). The empty specification
    (``true``) has no clauses and gives an empty list. ``chains=True`` leaves out the orders the
    others imply (:meth:`Specification.implied_orders`): "a before c" when "a before b" and
    "b before c" are said.

    Examples
    --------
    >>> from bsi_sklearn import Specification
    >>> spec = Specification(globals=["safe"], eventuals=["a"], orders=[("a", "b")])
    >>> for s in describe_specification(spec, {"safe": "the robot is safe"}):
    ...     print(s)
    Always, the robot is safe.
    Eventually, a holds.
    a holds before b holds.
    >>> chain = Specification(orders=[("a", "b"), ("b", "c")])
    >>> describe_specification(chain, chains=True)
    ['a holds before b holds.', 'b holds before c holds.']
    """
    return _sentences(specification,
                      lambda clause, conditions: clause_sentence(clause, conditions, descriptions,
                                                                 negations=negations),
                      chains)


def violated_clauses(specification, trace, feature_names=None):
    """The clauses of a specification that a demonstration violates.

    Each clause is evaluated on its own, as the one-clause specification of
    :func:`clause_specification` (:meth:`Specification.satisfied_by` semantics). A clause whose
    condition is false at the first step is satisfied (vacuously).

    Parameters
    ----------
    specification : Specification
    trace : array-like of shape (T, n_props) or pandas.DataFrame
    feature_names : sequence, default=None
        Column names of ``trace``; taken from the DataFrame columns when omitted.

    Returns
    -------
    list of tuple
        Violated clause keys, in :func:`ordered_clauses` order.

    Examples
    --------
    >>> import numpy as np
    >>> from bsi_sklearn import Specification
    >>> spec = Specification(globals=["safe"], eventuals=["a", "b"], orders=[("a", "b")])
    >>> trace = np.array([[1, 0, 0], [0, 0, 1], [1, 1, 1]])  # b before a, unsafe once
    >>> violated_clauses(spec, trace, feature_names=["safe", "a", "b"])
    [('G', 'safe'), ('U', 'a', 'b')]
    """
    spec = _check_spec(specification)
    cond = spec.conditions
    return [c for c in ordered_clauses(spec)
            if not clause_specification(c, cond).satisfied_by(trace, feature_names)]


def _pattern_sentence(clause):
    # The template's own reading (instance_text): "Response(a, b): every a is ... b."; the
    # propositions by name (descriptions are not woven into a template's sentence).
    return f"{instance_text(clause[1], [str(p) for p in clause[2]])}."


def _check_spec(spec):
    if not isinstance(spec, Specification):
        raise ValueError(f"specification must be a Specification, got {type(spec).__name__}")
    return spec


def _clause_condition(clause, conditions):
    if clause[0] in ("G", "P"):
        return None
    return conditions.get(clause[1])


def _difference(spec, reference, negations=None):
    """Clauses added to (+) and removed from (-) ``reference`` to obtain ``spec``."""
    mine, ref = spec.clauses(), reference.clauses()
    added = [f"+ {clause_specification(k, spec.conditions).readable(negations=negations)}"
             for k in ordered_clauses(spec) if k not in ref]
    removed = [f"- {clause_specification(k, reference.conditions).readable(negations=negations)}"
               for k in ordered_clauses(reference) if k not in mine]
    return "; ".join(added + removed)


def _short_label(key):
    if key[0] == "G":
        return f"G({key[1]})"
    if key[0] == "F":
        return f"F({key[1]})"
    if key[0] == "P":
        return f"{key[1]}({', '.join(map(str, key[2]))})"
    return f"{key[1]} before {key[2]}"

