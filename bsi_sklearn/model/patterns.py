"""The pattern library (DESIGN §12): named LTLf templates, their instances and their truth.

Each template is defined once, in :data:`TEMPLATES`: its name, its placeholders, its LTLf
formula (placeholders as atoms) and a plain-words sentence. :func:`pattern_truth` computes
the truth of instantiated templates on every demonstration, one pass over each trace per
clause, with a small numba recurrence per template (no formula interpreter in the loop).

Semantics (De Giacomo & Vardi's LTLf, the Declare definitions of Declare4Py / MINERful):
formulas are read at step 0 of a finite trace, ``X`` is the *strong* next (false at the
last step), ``WX`` the weak next (true at the last step), ``U`` the strong until, ``F`` / ``G``
range over the current and the later steps. The formula text is in the flloat / LTLf2DFA
syntax, so ``flloat``'s parser reads it as written.

Traces here are *state* traces (DESIGN §1): at each step any number of propositions may hold,
not one activity per step. The templates are read over propositions holding at steps, so two
placeholders may hold at the same step: ``Response(a, b)`` is satisfied by an ``a`` whose ``b``
is at the same step (``F`` includes the present), ``Precedence(a, b)`` by an ``a`` at the step of
the first ``b``, ``NotSuccession(a, b)`` is violated by ``a`` and ``b`` at one step. The
empty trace is not a demonstration (DESIGN §1: ``T_i >= 1``); :func:`pattern_truth` refuses it.
"""

import re
from itertools import combinations, permutations
from typing import NamedTuple

import numpy as np

from bsi_sklearn.model._ltlf_program import (
    compile_program,
    parse_ltlf,
    placeholders,
    program_truth,
)
from bsi_sklearn.model._pattern_kernels import catalogue_truth

__all__ = ["Template", "TEMPLATES", "FAMILIES", "get_template", "instantiate", "pattern_truth",
           "instance_ltlf", "instance_text"]

#: Most placeholders a user template may have: its instances grow as n_props ** slots.
MAX_SLOTS = 3


class Template(NamedTuple):
    """One LTLf template: its ``name``, ``slots`` (placeholder atoms), ``formula``, ``sentence``.

    ``symmetric`` templates have the same truth under any order of their slots, so
    :func:`instantiate` lists them once per set of propositions. ``family`` groups templates
    for the prior (one inclusion probability a family). ``code`` selects the catalogue's
    kernel; -1 marks a user template, evaluated from its formula.
    """

    name: str
    slots: tuple
    formula: str
    sentence: str
    symmetric: bool
    family: str
    code: int


_PRECEDENCE = "((!b U a) | G(!b))"

_DEFINITIONS = [
    # Declare, unary
    ("Existence", ("a",), "F(a)", "a happens at least once", False, "existence"),
    ("Absence", ("a",), "!F(a)", "a never happens", False, "absence"),
    ("AtMostOnce", ("a",), "!F(a & X(F(a)))", "a happens at most once (at most one step)",
     False, "absence"),
    ("Init", ("a",), "a", "a holds at the first step", False, "existence"),
    # Declare, binary
    ("RespondedExistence", ("a", "b"), "F(a) -> F(b)",
     "if a happens, b happens too (before, at or after it)", False, "relation"),
    ("CoExistence", ("a", "b"), "(F(a) -> F(b)) & (F(b) -> F(a))",
     "a and b both happen or neither does", True, "relation"),
    ("Response", ("a", "b"), "G(a -> F(b))",
     "every a is eventually followed by b", False, "relation"),
    ("Precedence", ("a", "b"), _PRECEDENCE,
     "b happens only after a has happened", False, "relation"),
    ("Succession", ("a", "b"), f"G(a -> F(b)) & {_PRECEDENCE}",
     "every a is eventually followed by b, and b happens only after a", False, "relation"),
    ("AlternateResponse", ("a", "b"), "G(a -> X(!a U b))",
     "every a is followed by b before the next a", False, "ordering"),
    ("AlternatePrecedence", ("a", "b"), f"{_PRECEDENCE} & G(b -> WX{_PRECEDENCE})",
     "every b is preceded by a, with no other b in between", False, "ordering"),
    ("ChainResponse", ("a", "b"), "G(a -> X(b))",
     "every a is immediately followed by b at the next step", False, "ordering"),
    ("ChainPrecedence", ("a", "b"), "G(X(b) -> a)",
     "every b after the first step is immediately preceded by a", False, "ordering"),
    ("NotCoExistence", ("a", "b"), "!(F(a) & F(b))",
     "a and b never both happen", True, "negation"),
    ("NotSuccession", ("a", "b"), "G(a -> !F(b))",
     "b never happens at or after an a", False, "negation"),
    # Dwyer's occurrence patterns, scoped
    ("AbsenceBefore", ("a", "r"), "F(r) -> (!a U r)", "a never happens before the first r",
     False, "scoped"),
    ("ExistenceBefore", ("a", "r"), "G(!r) | (!r U (a & !r))",
     "if r happens, a happens before the first r", False, "scoped"),
    ("UniversalityBefore", ("a", "r"), "F(r) -> (a U r)",
     "if r happens, a holds at every step before the first r", False, "scoped"),
    ("AbsenceAfter", ("a", "q"), "G(q -> G(!a))",
     "a never happens from the first q on", False, "scoped"),
    ("ExistenceAfter", ("a", "q"), "G(!q) | F(q & F(a))",
     "if q happens, a happens at or after it", False, "scoped"),
    ("UniversalityAfter", ("a", "q"), "G(q -> G(a))", "a holds at every step from the first q on",
     False, "scoped"),
    # disjunction of existence
    ("Choice", ("a", "b"), "F(a) | F(b)", "a or b happens at least once", True, "choice"),
    # occurrence everywhere (Dwyer's universality, globally) and together
    ("Universality", ("a",), "G(a)", "a holds at every step", False, "existence"),
    ("CoOccurrence", ("a", "b"), "F(a & b)", "a and b hold together at some step", True,
     "choice"),
]

#: Every template by name, in the order of the catalogue.
TEMPLATES = {row[0]: Template(*row, code) for code, row in enumerate(_DEFINITIONS)}

#: The families, in catalogue order, with ``"user"`` for templates given as formulas.
FAMILIES = tuple(dict.fromkeys(t.family for t in TEMPLATES.values())) + ("user",)


def get_template(template):
    """A :class:`Template` from a catalogue name, an LTLf formula with placeholders, or itself.

    A name (``"Response"``; a single capitalised word) is looked up in :data:`TEMPLATES`. Any
    other text is read as LTLf (flloat's syntax; ``X`` is the strong next, ``WX`` the weak
    one) whose every name is a placeholder, in the order they first appear: ``"G(x -> F(y))"``
    has slots ``("x", "y")``.

    Raises
    ------
    ValueError
        For an unknown name (the known ones listed), text that is not a formula (the
        position named), a formula without placeholders or with more than ``MAX_SLOTS``.

    Examples
    --------
    >>> get_template("Response").formula
    'G(a -> F(b))'
    >>> get_template("G(x -> F(y))").slots
    ('x', 'y')
    """
    if isinstance(template, Template):
        return template
    if not isinstance(template, str):
        raise TypeError(f"a template is a name or an LTLf string, got {type(template).__name__}")
    text = template.strip()
    if text in TEMPLATES:
        return TEMPLATES[text]
    if re.fullmatch(r"[A-Z][A-Za-z0-9_]*", text):  # a capitalised word: a name, misspelt
        raise ValueError(f"unknown template {template!r}; the known templates are: "
                         f"{', '.join(TEMPLATES)} (or give an LTLf formula with placeholders, "
                         "such as 'G(x -> F(y))')")
    slots = placeholders(parse_ltlf(text))
    if not slots:
        raise ValueError(f"the template {template!r} has no placeholder: its truth is the same "
                         "on every demonstration")
    if len(slots) > MAX_SLOTS:
        raise ValueError(f"the template {template!r} has {len(slots)} placeholders "
                         f"({', '.join(slots)}); at most {MAX_SLOTS} are allowed, as its "
                         "instances grow as the number of propositions to that power")
    return Template(text, slots, text, f"{text} holds", False, "user", -1)


def instantiate(template, names):
    """Every instance of ``template`` over ``names``: tuples of distinct propositions.

    Ordered tuples (permutations) for an asymmetric template, sets in the order of ``names``
    (combinations) for a symmetric one.

    Examples
    --------
    >>> instantiate("Response", ["x", "y"])
    [('x', 'y'), ('y', 'x')]
    >>> instantiate("Choice", ["x", "y", "z"])
    [('x', 'y'), ('x', 'z'), ('y', 'z')]
    """
    t = get_template(template)
    pick = combinations if t.symmetric else permutations
    return list(pick(list(names), len(t.slots)))


def pattern_truth(template, data, offsets, columns):
    """Truth of instances of ``template`` on every demonstration.

    Parameters
    ----------
    template : str or Template
    data : ndarray of shape (sum(T_i), n_props)
        The stacked demonstrations (``Traces.data``), bool or 0/1.
    offsets : ndarray of shape (n_demos + 1,)
        Demonstration ``i`` is ``data[offsets[i]:offsets[i + 1]]`` (``Traces.offsets``).
    columns : array-like of shape (n_instances, n_slots)
        For each instance, the column of each slot, in the template's slot order.

    Returns
    -------
    truth : ndarray of shape (n_demos, n_instances), dtype uint8
        ``truth[i, k]`` is 1 when demonstration ``i`` satisfies instance ``k``
        (:func:`bsi_sklearn.model.clauses.pack_rows` packs it like the clause truth).

    Examples
    --------
    >>> data = np.array([[1, 0], [0, 1], [1, 0]], dtype=np.uint8)
    >>> pattern_truth("Response", data, np.array([0, 3]), [[0, 1], [1, 0]]).tolist()
    [[0, 1]]
    """
    t = get_template(template)
    data = np.ascontiguousarray(data, dtype=np.uint8)
    offsets = np.ascontiguousarray(offsets, dtype=np.int64)
    cols = np.asarray(columns, dtype=np.int64).reshape(-1, len(t.slots))
    if data.ndim != 2:
        raise ValueError(f"data must be 2-D (steps, propositions), got shape {data.shape}")
    lengths = np.diff(offsets)
    if offsets.ndim != 1 or offsets.shape[0] < 1 or offsets[0] != 0 \
            or offsets[-1] != data.shape[0] or np.any(lengths < 0):
        raise ValueError("offsets must rise from 0 to the number of rows of data")
    if np.any(lengths == 0):
        raise ValueError(f"demonstration {int(np.argmax(lengths == 0))} has no step; "
                         "a demonstration has at least one step")
    if cols.size and (cols.min() < 0 or cols.max() >= data.shape[1]):
        raise ValueError(f"a column index is outside 0..{data.shape[1] - 1}")
    out = np.zeros((offsets.shape[0] - 1, cols.shape[0]), dtype=np.uint8)
    if t.code < 0:
        program = compile_program(parse_ltlf(t.formula), t.slots)
        program_truth(program, data, offsets, np.ascontiguousarray(cols), out)
    else:
        if cols.shape[1] == 1:  # the kernels take two columns; a unary template reads one
            cols = np.concatenate([cols, cols], axis=1)
        catalogue_truth(t.code, data, offsets, np.ascontiguousarray(cols), out)
    return out


def _check_instance(t, names):
    names = [str(n) for n in names]
    if len(names) != len(t.slots):
        raise ValueError(f"the template {t.name!r} has {len(t.slots)} slots "
                         f"({', '.join(t.slots)}), got {len(names)} propositions {names}")
    return names


def instance_ltlf(template, names, dialect="ltlf2dfa"):
    """The formula of one instance, its placeholders replaced by the propositions' atoms.

    Parameters
    ----------
    template : str or Template
    names : sequence of str
        The propositions filling the slots, in the template's slot order.
    dialect : {"ltlf2dfa", "spot"}, default="ltlf2dfa"
        ``"ltlf2dfa"``: flloat / LTLf2DFA text (a name those parsers cannot read as an atom is
        a ``ValueError`` saying why); ``"spot"``: atoms quoted where Spot needs it (Spot reads
        ``X`` as the strong next only in its LTLf mode: the text is LTLf).

    Examples
    --------
    >>> instance_ltlf("Response", ["order", "pay"])
    'G(order -> F(pay))'
    >>> instance_ltlf("G(x -> F(y))", ["Fee", "ship"], dialect="spot")  # F...: an operator
    'G("Fee" -> F(ship))'
    """
    # Imported here: the export's atom rules serve this text only, not the truth computed above.
    from bsi_sklearn.specification.ltlf_export import ltlf_atom_problem, spot_atom

    t = get_template(template)
    names = _check_instance(t, names)
    if dialect not in ("ltlf2dfa", "spot"):
        raise ValueError(f"dialect must be 'ltlf2dfa' or 'spot', got {dialect!r}")
    atoms = {}
    for slot, name in zip(t.slots, names):
        if dialect == "spot":
            atoms[slot] = spot_atom(name)
        else:
            problem = ltlf_atom_problem(name)
            if problem is not None:
                raise ValueError(f"proposition {name!r} cannot be an LTLf2DFA / flloat atom: "
                                 f"{problem}; use dialect='spot' or rename it")
            atoms[slot] = name
    # Rewrite the formula's own tokens: a placeholder never matches inside another name.
    return re.sub(r"[A-Za-z_][A-Za-z0-9_]*", lambda m: atoms.get(m.group(0), m.group(0)),
                  t.formula)


def instance_text(template, names):
    """``Name(p, q): reading`` of one instance, in the propositions' names.

    Examples
    --------
    >>> instance_text("Response", ["order", "pay"])
    'Response(order, pay): every order is eventually followed by pay'
    >>> instance_text("AbsenceAfter", ["refund", "ship"])
    'AbsenceAfter(refund, ship): refund never happens from the first ship on'
    """
    t = get_template(template)
    names = _check_instance(t, names)
    if t.code < 0:
        return f"{instance_ltlf(t, names, dialect='spot')} holds"
    table = dict(zip(t.slots, names))
    reading = re.sub(r"\b[a-z]\b", lambda m: table.get(m.group(0), m.group(0)), t.sentence)
    return f"{t.name}({', '.join(names)}): {reading}"
