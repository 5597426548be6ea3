"""The template catalogue of pattern clauses (DESIGN §12) and the LTLf text it is written in.

Each template is defined once, in :data:`TEMPLATES`: its name, its placeholders, its LTLf
formula (placeholders as atoms) and a plain-words sentence; :func:`get_template` also reads a
user template given as LTLf text with placeholders (:func:`parse_ltlf`: the flloat / LTLf2DFA
syntax, ``!``, ``&``, ``|``, ``->``, ``<->``, ``X`` strong next, ``WX`` weak next, ``F``,
``G``, ``U``, ``R``, ``true``, ``false``; every other name is a placeholder). What a template
*is* sits here, beside the value type that holds its instances; its truth on demonstrations is
computed in the model (:mod:`bsi_sklearn.model.patterns`).

Semantics (De Giacomo & Vardi's LTLf, the Declare definitions of Declare4Py / MINERful):
formulas are read at step 0 of a finite trace, ``X`` is the *strong* next (false at the
last step), ``WX`` the weak next (true at the last step), ``U`` the strong until, ``F`` / ``G``
range over the current and the later steps. The formula text is in the flloat / LTLf2DFA
syntax, so ``flloat``'s parser reads it as written.

Traces here are *state* traces (DESIGN §1): at each step any number of propositions may hold,
not one activity per step. The templates are read over propositions holding at steps, so two
placeholders may hold at the same step: ``Response(a, b)`` is satisfied by an ``a`` whose ``b``
is at the same step (``F`` includes the present), ``Precedence(a, b)`` by an ``a`` at the step of
the first ``b``, ``NotSuccession(a, b)`` is violated by ``a`` and ``b`` at one step.
"""

import re
from itertools import combinations, permutations
from typing import NamedTuple

from bsi_sklearn.specification._atoms import ltlf_atom_problem, spot_atom

__all__ = ["Template", "TEMPLATES", "FAMILIES", "MAX_SLOTS", "get_template", "instantiate",
           "instance_ltlf", "instance_text", "pattern_order", "parse_ltlf", "placeholders",
           "OPCODES", "fill_formula", "TEMPLATE_SETS"]

_ATOM, _TRUE, _FALSE, _NOT, _AND, _OR, _IMPLIES, _EQUIV = range(8)
_NEXT, _WEAK_NEXT, _EVENTUALLY, _GLOBALLY, _UNTIL, _RELEASE = range(8, 14)
_UNARY = {"!": _NOT, "X": _NEXT, "WX": _WEAK_NEXT, "F": _EVENTUALLY, "G": _GLOBALLY}
_BINARY = {"&": _AND, "|": _OR, "->": _IMPLIES, "<->": _EQUIV, "U": _UNTIL, "R": _RELEASE}
#: The operator codes of a formula's tree (nested tuples ``(code, child, ...)``), by name.
OPCODES = {"atom": _ATOM, "true": _TRUE, "false": _FALSE, "not": _NOT, "and": _AND, "or": _OR,
           "implies": _IMPLIES, "equiv": _EQUIV, "next": _NEXT, "weak_next": _WEAK_NEXT,
           "eventually": _EVENTUALLY, "globally": _GLOBALLY, "until": _UNTIL,
           "release": _RELEASE}
_RESERVED = {"X", "WX", "F", "G", "U", "R", "true", "false"}
_TOKEN = re.compile(r"\s*(<->|->|[()!&|]|[A-Za-z_][A-Za-z0-9_]*)")


def _tokens(text):
    out, pos, end = [], 0, len(text.rstrip())
    while pos < end:
        m = _TOKEN.match(text, pos)
        if m is None:
            at = pos + len(text[pos:]) - len(text[pos:].lstrip())  # past the blanks
            raise ValueError(f"unexpected character {text[at]!r} at position {at} in the "
                             f"template {text!r}")
        out.append((m.group(1), m.start(1)))
        pos = m.end()
    return out


def parse_ltlf(text):
    """The tree of an LTLf formula: nested tuples ``(op, child, ...)`` or ``(ATOM, name)``.

    Precedence, loosest first, as flloat reads it: ``<->``, ``->``, ``|``, ``&``, ``U`` and
    ``R`` (right-associative), then the unary operators. The chains ``x -> y -> z`` and
    ``x <-> y <-> z`` are refused: flloat reads the first from the left (most readers from
    the right), the second as "all equal".

    Raises
    ------
    ValueError
        Naming the position and the text, for anything that is not a formula.

    Examples
    --------
    >>> parse_ltlf("G(a -> F(b))") == (11, (6, (0, 'a'), (10, (0, 'b'))))
    True
    """
    if not isinstance(text, str):
        raise TypeError(f"a template must be a string, got {type(text).__name__}")
    toks = _tokens(text)
    if not toks:
        raise ValueError("the template is empty")
    pos = [0]

    def peek():
        return toks[pos[0]][0] if pos[0] < len(toks) else None

    def fail(what):
        at = toks[pos[0]][1] if pos[0] < len(toks) else len(text)
        found = f"{toks[pos[0]][0]!r}" if pos[0] < len(toks) else "the end"
        raise ValueError(f"expected {what} at position {at} in the template {text!r}, "
                         f"found {found}")

    def binary(level):
        # Loosest first, as flloat reads them: <->, ->, |, &, then U and R.
        ops = [("<->",), ("->",), ("|",), ("&",), ("U", "R")][level]
        left = binary(level + 1) if level < 4 else unary()
        while peek() in ops:
            op = _BINARY[peek()]
            pos[0] += 1
            if level == 4:  # right-associative: x U y U z is x U (y U z)
                return (op, left, binary(level))
            right = binary(level + 1)
            if level < 2 and peek() == ops[0]:
                # flloat folds x -> y -> z from the left, most texts mean the right, and
                # reads x <-> y <-> z as "all equal": refuse both chains.
                fail(f"parentheses around one of the {ops[0]} (x {ops[0]} y {ops[0]} z is "
                     "ambiguous); an operator")
            left = (op, left, right)
        return left

    def unary():
        tok = peek()
        if tok is None:
            fail("a formula")
        pos[0] += 1
        if tok in _UNARY:
            return (_UNARY[tok], unary())
        if tok == "(":
            inner = binary(0)
            if peek() != ")":
                fail("')'")
            pos[0] += 1
            return inner
        if tok == "true":
            return (_TRUE,)
        if tok == "false":
            return (_FALSE,)
        if tok in _RESERVED or not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", tok):
            pos[0] -= 1
            fail("a placeholder, a constant, '(' or a unary operator")
        return (_ATOM, tok)

    tree = binary(0)
    if pos[0] != len(toks):
        fail("an operator or the end")
    return tree


def placeholders(tree):
    """The placeholder names of a tree, in the order they first appear."""
    seen = []

    def walk(node):
        if node[0] == _ATOM:
            if node[1] not in seen:
                seen.append(node[1])
        else:
            for child in node[1:]:
                walk(child)

    walk(tree)
    return tuple(seen)


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

#: Named sets of catalogue templates, each in catalogue order: ``"unary"`` the templates of one
#: slot (their instances grow linearly with the propositions), ``"declare"`` the Declare
#: language's templates (no Dwyer scopes), ``"all"`` the whole catalogue.
TEMPLATE_SETS = {
    "unary": tuple(name for name, t in TEMPLATES.items() if len(t.slots) == 1),
    "declare": ("Existence", "Absence", "AtMostOnce", "Init", "RespondedExistence",
                "CoExistence", "Response", "Precedence", "Succession", "AlternateResponse",
                "AlternatePrecedence", "ChainResponse", "ChainPrecedence", "NotCoExistence",
                "NotSuccession", "Choice"),
    "all": tuple(TEMPLATES),
}

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
        a ``ValueError`` saying why); ``"spot"``: atoms quoted where Spot needs it, the strong
        next written ``X[!]`` and the weak next ``!X[!]!`` (plain ``X`` is weak in Spot's LTLf
        reading, strong in its LTL one: this text means the same in both). The text is LTLf:
        give it to Spot through ``spot.from_ltlf``.

    Examples
    --------
    >>> instance_ltlf("Response", ["order", "pay"])
    'G(order -> F(pay))'
    >>> instance_ltlf("G(x -> F(y))", ["Fee", "ship"], dialect="spot")  # F...: an operator
    'G("Fee" -> F(ship))'
    """
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
    return fill_formula(t, [atoms[slot] for slot in t.slots], dialect)


def fill_formula(template, atoms, dialect="ltlf2dfa"):
    """A template's formula with each slot replaced by the atom text given, in a dialect.

    No check is made on ``atoms`` (already written for the dialect, such as ``q`` or
    ``(!q)``); ``"spot"`` writes the nexts as :func:`instance_ltlf` says.

    Examples
    --------
    >>> fill_formula("ChainResponse", ["(!q)", "r"], dialect="spot")
    'G((!q) -> X[!](r))'
    """
    t = get_template(template)
    table = dict(zip(t.slots, atoms))
    if dialect == "spot":
        table.update({"X": "X[!]", "WX": "!X[!]!"})
    # Rewrite the formula's own tokens: a placeholder never matches inside another name.
    return re.sub(r"[A-Za-z_][A-Za-z0-9_]*", lambda m: table.get(m.group(0), m.group(0)),
                  t.formula)


def pattern_order(key):
    """Sort key of a pattern clause ``(template name, propositions)``.

    The catalogue's templates by name, then user templates (their LTLf text); propositions of
    mixed types compare by type name first. Every listing of a specification's pattern
    clauses (its text, its automaton, the sentences) follows it.

    Examples
    --------
    >>> sorted([("{x}", ("a",)), ("Response", (2, "b")), ("Absence", ("c",))],
    ...        key=pattern_order)
    [('Absence', ('c',)), ('Response', (2, 'b')), ('{x}', ('a',))]
    """
    name, props = key
    return (name not in TEMPLATES, name, tuple((type(p).__name__, p) for p in props))


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
        # the template's own syntax (WX, not Spot's X[!]), atoms quoted where needed
        return f"{fill_formula(t, [spot_atom(n) for n in names])} holds"
    table = dict(zip(t.slots, names))
    reading = re.sub(r"\b[a-z]\b", lambda m: table.get(m.group(0), m.group(0)), t.sentence)
    return f"{t.name}({', '.join(names)}): {reading}"

