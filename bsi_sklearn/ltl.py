"""A small general LTL formula on finite traces: parsing, evaluation, and the BSI template."""

from __future__ import annotations

import re
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from bsi_sklearn.specification import Specification
from bsi_sklearn.traces import check_traces

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

# Padded evaluation holds (demos x steps) booleans per subformula; chunks stay below this.
_MAX_CELLS = 4_000_000


class Formula:
    """Base class of LTL formulas over named propositions (immutable, hashable).

    Semantics follow DESIGN section 3: a formula is evaluated at ``t = 0`` on the infinite
    word made of the finite trace whose **last state repeats forever**. Hence ``G p`` holds
    when ``p`` holds at every step, ``F p`` when it holds at some step, ``a U b`` when some
    step has ``b`` and every earlier step has ``a``, and ``X phi`` at the last step reads
    ``phi`` on the (repeated) last state. For formulas without ``X`` this coincides with
    the usual LTLf semantics; on the last step ``X`` differs from LTLf's strong next (false
    there) and weak next (true there).

    Build formulas with :func:`parse_ltl` (prefix notation of samples2LTL / Scarlet such as
    ``"&(F(a),G(!(b)))"``, or infix such as ``"F(a) & G(!b)"``), with the node classes, or
    with the operators ``&``, ``|`` and ``~``.

    See Also
    --------
    parse_ltl : Parse prefix or infix text.
    bsi_sklearn.specification.Specification : The BSI template formula.

    Examples
    --------
    >>> import numpy as np
    >>> phi = parse_ltl("&(F(a),G(!(b)))")
    >>> print(phi)
    F(a) & G(!b)
    >>> phi.to_prefix()
    '&(F(a),G(!(b)))'
    >>> trace = np.array([[0, 0], [1, 0]])            # columns a, b
    >>> phi.satisfied_by(trace, feature_names=["a", "b"])
    True
    >>> phi.to_specification()
    Specification(globals=['!b'], eventuals=['a'], orders=[])
    """

    __slots__ = ()

    # -- structure ---------------------------------------------------------------------
    @property
    def children(self):
        """Direct subformulas, in order."""
        return ()

    def subformulas(self):
        """Every subformula (this one included), children before parents."""
        out = []
        for child in self.children:
            out.extend(child.subformulas())
        out.append(self)
        return out

    @property
    def atoms(self):
        """Names of the propositions the formula mentions (frozenset of str)."""
        return frozenset(f.name for f in self.subformulas() if isinstance(f, Atom))

    @property
    def size(self):
        """Number of nodes of the syntax tree."""
        return len(self.subformulas())

    @property
    def depth(self):
        """Operators on the longest root-to-leaf path (an atom has depth 0).

        This is the formula depth of samples2LTL's ``.trace`` files: ``G(x0)`` has depth 1,
        ``G(!(x0))`` depth 2.
        """
        if not self.children:
            return 0
        return 1 + max(c.depth for c in self.children)

    def __and__(self, other):
        return And(self, _as_formula(other))

    def __or__(self, other):
        return Or(self, _as_formula(other))

    def __invert__(self):
        return Not(self)

    def __repr__(self):
        return f"parse_ltl({self.to_prefix()!r})"

    def __str__(self):
        return self._infix(top=True)

    # -- rendering ---------------------------------------------------------------------
    def to_prefix(self):
        """Render in the prefix notation of samples2LTL / Scarlet, e.g. ``&(F(a),G(!(b)))``."""
        raise NotImplementedError

    def to_infix(self):
        """Render in infix notation (the format :meth:`Specification.to_ltl` uses)."""
        return self._infix(top=True)

    def _infix(self, top=False):
        raise NotImplementedError

    # -- evaluation --------------------------------------------------------------------
    def evaluate(self, X, feature_names=None):
        """Truth of the formula at ``t = 0`` on every demonstration.

        Parameters
        ----------
        X : demonstrations
            Any format of DESIGN section 1 (list of ``(T_i, n_props)`` arrays or DataFrames,
            3-D array, 2-D array of length-one traces).
        feature_names : sequence of str, default=None
            Proposition names of the columns; taken from the DataFrame columns when omitted.
            Atoms whose name is a decimal integer (``"3"``) that is not a column name read
            that column index.

        Returns
        -------
        satisfied : ndarray of shape (n_demos,), dtype bool
        """
        traces = check_traces(X, estimator_name="Formula.evaluate")
        return self._evaluate_traces(traces, feature_names)

    def satisfied_by(self, trace, feature_names=None):
        """Truth of the formula at ``t = 0`` on one trace ``(T, n_props)`` (array or frame)."""
        return bool(self.evaluate([trace], feature_names=feature_names)[0])

    def _evaluate_traces(self, traces, feature_names):
        names = feature_names if feature_names is not None else traces.feature_names
        columns = _resolve_atoms(self.atoms, names, traces.n_props)
        atom_list = sorted(columns)
        used = traces.data[:, [columns[a] for a in atom_list]].astype(bool)
        columns = {a: k for k, a in enumerate(atom_list)}
        lengths = traces.lengths
        result = np.empty(traces.n_demos, dtype=bool)
        order = np.argsort(lengths, kind="stable")
        start = 0
        while start < len(order):
            # Group demonstrations of similar length; pad each by repeating its last state,
            # which leaves the infinite word (and so every truth value) unchanged.
            t_max = int(lengths[order[start]])
            stop = start + 1
            while stop < len(order):
                t_next = int(lengths[order[stop]])
                if (stop - start + 1) * t_next > _MAX_CELLS and stop > start:
                    break
                t_max = t_next
                stop += 1
            idx = order[start:stop]
            steps = np.minimum(np.arange(t_max)[None, :], lengths[idx, None] - 1)
            rows = traces.offsets[idx, None] + steps
            cube = used[rows]  # (n, t_max, n_atoms)
            cache = {}
            value = self._eval(cube, columns, cache)
            result[idx] = value[:, 0]
            start = stop
        return result

    def _eval(self, cube, columns, cache):
        key = id(self)
        if key not in cache:
            cache[key] = (self, self._compute(cube, columns, cache))
        return cache[key][1]

    def _compute(self, cube, columns, cache):
        raise NotImplementedError

    # -- the BSI template --------------------------------------------------------------
    def to_specification(self, names=None, negation_prefix="!"):
        """The equivalent :class:`Specification`, or ``None`` when outside the template.

        The template is a conjunction of ``G(p)``, ``F(w)``, ``pi -> F(w)``,
        ``(!b U a)`` and ``pi -> (!b U a)`` clauses over propositions (DESIGN section 2).
        Literals are read as propositions: ``!p`` becomes the proposition named
        ``negation_prefix + p`` (the column :class:`~bsi_sklearn.preprocessing.NegationAugmenter`
        adds), so ``G(!p)`` is in the template through ``G("!p")`` and ``(p U a)`` through
        ``(!"!p" U a)``. ``G`` distributes over ``&``; ``true U a`` and ``!a U a`` read as
        ``F(a)``; ``l | C`` reads as ``!l -> C``.

        ``None`` is returned when the formula has another shape (disjunctions of clauses,
        nested temporal operators such as ``F(a & F(b))``, ``G(p -> q)``...), when one
        subtask would need two different conditions, or when the transitive closure the
        :class:`Specification` stores would add an order the formula does not imply (an
        intermediate subtask with a condition).

        Parameters
        ----------
        names : sequence or mapping, default=None
            Identifiers to use. A sequence lists the available propositions (an element
            matches a proposition name when equal to it or when its ``str`` is); a mapping
            translates proposition names to identifiers (e.g. ``{"x0": 0}``). A proposition
            that is not available makes the result ``None``. ``None`` keeps the names.
        negation_prefix : str, default="!"
            Prefix naming negated propositions.

        Returns
        -------
        spec : Specification or None

        Examples
        --------
        >>> parse_ltl("&(G(x0),F(x1))").to_specification()
        Specification(globals=['x0'], eventuals=['x1'], orders=[])
        >>> parse_ltl("G(!(x0))").to_specification(names=["x0", "!x0"])
        Specification(globals=['!x0'], eventuals=[], orders=[])
        >>> parse_ltl("G(!(x0))").to_specification(names=["x0"]) is None
        True
        >>> parse_ltl("F(&(a,F(b)))").to_specification() is None
        True
        """
        return _to_specification(self, names, negation_prefix)


def _as_formula(value):
    if isinstance(value, Formula):
        return value
    if isinstance(value, bool):
        return Constant(value)
    if isinstance(value, str):
        return parse_ltl(value)
    raise TypeError(f"cannot combine a formula with {type(value).__name__}")


def _resolve_atoms(atoms, names, n_props):
    columns = {}
    lookup = None
    if names is not None:
        names = [str(n) for n in names]
        if len(names) != n_props:
            raise ValueError(
                f"feature_names has {len(names)} entries for traces with {n_props} propositions"
            )
        lookup = {n: i for i, n in enumerate(names)}
    for atom in sorted(atoms):
        if lookup is not None and atom in lookup:
            columns[atom] = lookup[atom]
        elif atom.isdecimal() and int(atom) < n_props:
            columns[atom] = int(atom)
        elif lookup is None:
            raise ValueError(
                f"proposition {atom!r} cannot be resolved: the traces have no proposition "
                "names; pass feature_names or DataFrames"
            )
        else:
            raise ValueError(
                f"proposition {atom!r} is not among the trace propositions "
                f"{names[:20]}{' ...' if len(names) > 20 else ''}"
            )
    return columns


# -- nodes --------------------------------------------------------------------------------


@dataclass(frozen=True, repr=False)
class Atom(Formula):
    """A proposition, true at a step when its column is true."""

    name: str

    def __post_init__(self):
        if not isinstance(self.name, str) or not self.name:
            raise ValueError(f"an atom needs a non-empty string name, got {self.name!r}")

    def to_prefix(self):
        """Render in prefix notation."""
        return _quote(self.name)

    def _infix(self, top=False):
        return _quote(self.name)

    def _compute(self, cube, columns, cache):
        return cube[:, :, columns[self.name]]


@dataclass(frozen=True, repr=False)
class Constant(Formula):
    """``true`` or ``false``."""

    value: bool

    def to_prefix(self):
        """Render in prefix notation."""
        return "true" if self.value else "false"

    def _infix(self, top=False):
        return self.to_prefix()

    def _compute(self, cube, columns, cache):
        return np.full(cube.shape[:2], bool(self.value))


@dataclass(frozen=True, repr=False)
class _Unary(Formula):
    operand: Formula

    symbol = "?"

    def __post_init__(self):
        if not isinstance(self.operand, Formula):
            raise TypeError(f"{type(self).__name__} needs a Formula, got {self.operand!r}")

    @property
    def children(self):
        """Direct subformulas."""
        return (self.operand,)

    def to_prefix(self):
        """Render in prefix notation."""
        return f"{self.symbol}({self.operand.to_prefix()})"

    def _infix(self, top=False):
        inner = self.operand._infix()
        if isinstance(self, Not) and isinstance(self.operand, (Atom, Constant)):
            return f"!{inner}"
        if not inner.startswith("("):
            inner = f"({inner})"
        return f"{self.symbol}{inner}"


@dataclass(frozen=True, repr=False)
class _Binary(Formula):
    left: Formula
    right: Formula

    symbol = "?"

    def __post_init__(self):
        for arg in (self.left, self.right):
            if not isinstance(arg, Formula):
                raise TypeError(f"{type(self).__name__} needs Formulas, got {arg!r}")

    @property
    def children(self):
        """Direct subformulas."""
        return (self.left, self.right)

    def to_prefix(self):
        """Render in prefix notation."""
        return f"{self.symbol}({self.left.to_prefix()},{self.right.to_prefix()})"

    def _infix(self, top=False):
        parts = []
        for child in (self.left, self.right):
            # Left-nested chains of & or | print flat (a & b & c), as the parser folds left.
            if child is self.left and type(child) is type(self) and isinstance(self, (And, Or)):
                parts.append(child._infix(top=True))
            else:
                parts.append(child._infix())
        text = f" {self.symbol} ".join(parts)
        return text if top else f"({text})"


class Not(_Unary):
    """Negation ``!phi``."""

    symbol = "!"

    def _compute(self, cube, columns, cache):
        return ~self.operand._eval(cube, columns, cache)


class Next(_Unary):
    """``X phi``: ``phi`` at the next step; at the last step, on the repeated last state."""

    symbol = "X"

    def _compute(self, cube, columns, cache):
        v = self.operand._eval(cube, columns, cache)
        return np.concatenate([v[:, 1:], v[:, -1:]], axis=1)


class Eventually(_Unary):
    """``F phi``: ``phi`` at this or some later step."""

    symbol = "F"

    def _compute(self, cube, columns, cache):
        v = self.operand._eval(cube, columns, cache)
        return np.logical_or.accumulate(v[:, ::-1], axis=1)[:, ::-1]


class Globally(_Unary):
    """``G phi``: ``phi`` at this and every later step."""

    symbol = "G"

    def _compute(self, cube, columns, cache):
        v = self.operand._eval(cube, columns, cache)
        return np.logical_and.accumulate(v[:, ::-1], axis=1)[:, ::-1]


class And(_Binary):
    """Conjunction ``phi & psi``."""

    symbol = "&"

    def _compute(self, cube, columns, cache):
        return self.left._eval(cube, columns, cache) & self.right._eval(cube, columns, cache)


class Or(_Binary):
    """Disjunction ``phi | psi``."""

    symbol = "|"

    def _compute(self, cube, columns, cache):
        return self.left._eval(cube, columns, cache) | self.right._eval(cube, columns, cache)


class Implies(_Binary):
    """Implication ``phi -> psi``."""

    symbol = "->"

    def _compute(self, cube, columns, cache):
        return ~self.left._eval(cube, columns, cache) | self.right._eval(cube, columns, cache)


class Equivalent(_Binary):
    """Equivalence ``phi <-> psi``."""

    symbol = "<->"

    def _compute(self, cube, columns, cache):
        return self.left._eval(cube, columns, cache) == self.right._eval(cube, columns, cache)


def _until(a, b):
    # a U b at i  <=>  the first step j >= i with b comes no later than the first step
    # j' >= i without a (and such a j exists). Positions past the end repeat the last one,
    # so a witness beyond the trace implies one at the last step.
    n_steps = a.shape[1]
    never = n_steps
    steps = np.arange(n_steps)
    next_b = np.minimum.accumulate(np.where(b, steps, never)[:, ::-1], axis=1)[:, ::-1]
    next_not_a = np.minimum.accumulate(np.where(a, never, steps)[:, ::-1], axis=1)[:, ::-1]
    return (next_b < never) & (next_b <= next_not_a)


class Until(_Binary):
    """Strong until ``phi U psi``: ``psi`` at some step, ``phi`` at every step before."""

    symbol = "U"

    def _compute(self, cube, columns, cache):
        return _until(self.left._eval(cube, columns, cache),
                      self.right._eval(cube, columns, cache))


class Release(_Binary):
    """Release ``phi R psi``, i.e. ``!(!phi U !psi)``."""

    symbol = "R"

    def _compute(self, cube, columns, cache):
        return ~_until(~self.left._eval(cube, columns, cache),
                       ~self.right._eval(cube, columns, cache))


_UNARY = {"!": Not, "~": Not, "X": Next, "F": Eventually, "G": Globally}
_BINARY = {"&": And, "|": Or, "->": Implies, "<->": Equivalent, "U": Until, "R": Release}
_CONSTANTS = {"true": True, "false": False}
_RESERVED = {"X", "F", "G", "U", "R"}

_TOKEN = re.compile(
    r"(?:(?P<op><->|->|[!~&|(),])|(?P<name>[A-Za-z0-9_][A-Za-z0-9_.]*)"
    r"|\"(?P<quoted>[^\"]+)\")"
)
_PLAIN_NAME = re.compile(r"[A-Za-z0-9_][A-Za-z0-9_.]*")


def _quote(name):
    plain = _PLAIN_NAME.fullmatch(name) and name not in _RESERVED and name.lower() not in (
        _CONSTANTS
    )
    return name if plain else f'"{name}"'


def _tokenize(text):
    tokens, pos = [], 0
    while True:
        while pos < len(text) and text[pos].isspace():
            pos += 1
        if pos == len(text):
            return tokens
        m = _TOKEN.match(text, pos)
        if m is None:
            raise ValueError(
                f"unexpected character {text[pos]!r} at position {pos} in formula {text!r}"
            )
        if m.group("op"):
            tokens.append(("op", m.group("op"), pos))
        elif m.group("name") is not None:
            tokens.append(("name", m.group("name"), pos))
        else:
            tokens.append(("atom", m.group("quoted"), pos))
        pos = m.end()


class _Parser:
    def __init__(self, text):
        self.text = text
        self.tokens = _tokenize(text)
        self.i = 0

    def peek(self):
        return self.tokens[self.i] if self.i < len(self.tokens) else (None, None, len(self.text))

    def error(self, message):
        pos = self.peek()[2]
        return ValueError(f"{message} at position {pos} in formula {self.text!r}")

    def take(self, value=None):
        kind, tok, _ = self.peek()
        if kind is None:
            raise self.error("unexpected end" if value is None else f"expected {value!r}")
        if value is not None and tok != value:
            raise self.error(f"expected {value!r}, found {tok!r}")
        self.i += 1
        return kind, tok

    def done(self):
        if self.i != len(self.tokens):
            raise self.error(f"unexpected {self.peek()[1]!r}")

    def leaf(self, kind, tok):
        if kind == "atom":
            return Atom(tok)
        if kind == "name" and tok.lower() in _CONSTANTS:
            return Constant(_CONSTANTS[tok.lower()])
        if kind == "name" and tok not in _RESERVED:
            return Atom(tok)
        return None

    # prefix: OP(args) ------------------------------------------------------------------
    def prefix(self):
        kind, tok = self.take()
        node = self.leaf(kind, tok)
        if node is not None:
            return node
        if tok in _UNARY:
            self.take("(")
            arg = self.prefix()
            self.take(")")
            return _UNARY[tok](arg)
        if tok in _BINARY:
            self.take("(")
            args = [self.prefix()]
            while self.peek()[1] == ",":
                self.take(",")
                args.append(self.prefix())
            self.take(")")
            if len(args) < 2 or (len(args) > 2 and tok not in ("&", "|")):
                self.i -= 1
                raise self.error(f"operator {tok!r} takes 2 arguments, got {len(args)}")
            node = args[0]
            for arg in args[1:]:
                node = _BINARY[tok](node, arg)
            return node
        self.i -= 1
        raise self.error(f"unexpected {tok!r}")

    # infix, lowest to highest precedence: <->, ->, |, &, U/R, unary ---------------------
    def equivalence(self):
        node = self.implication()
        while self.peek()[1] == "<->":
            self.take()
            node = Equivalent(node, self.implication())
        return node

    def implication(self):
        node = self.disjunction()
        if self.peek()[1] == "->":
            self.take()
            return Implies(node, self.implication())
        return node

    def disjunction(self):
        node = self.conjunction()
        while self.peek()[1] == "|":
            self.take()
            node = Or(node, self.conjunction())
        return node

    def conjunction(self):
        node = self.until()
        while self.peek()[1] == "&":
            self.take()
            node = And(node, self.until())
        return node

    def until(self):
        node = self.unary()
        if self.peek()[0] == "name" and self.peek()[1] in ("U", "R"):
            _, tok = self.take()
            return _BINARY[tok](node, self.until())
        return node

    def unary(self):
        kind, tok = self.take()
        if kind in ("op", "name") and tok in _UNARY:
            return _UNARY[tok](self.unary())
        if tok == "(" and kind == "op":
            node = self.equivalence()
            self.take(")")
            return node
        node = self.leaf(kind, tok)
        if node is None:
            self.i -= 1
            raise self.error(f"unexpected {tok!r}")
        return node


def parse_ltl(text, notation="auto"):
    """Parse an LTL formula in prefix or infix notation.

    Prefix notation is the one of samples2LTL and Scarlet: ``OP(arg)`` for the unary
    operators ``!``, ``X``, ``F``, ``G`` and ``OP(left,right)`` for ``&``, ``|``, ``->``,
    ``<->``, ``U``, ``R`` (``&`` and ``|`` also accept more arguments, folded to the left),
    e.g. ``"->(F(x1),U(!(x0),x1))"``. Infix notation is what
    :meth:`Specification.to_ltl` prints: ``"G(safe) & F(a) & (b_ok -> F(b)) & (!b U a)"``,
    with precedence (loosest first) ``<->``, ``->`` (right-associative), ``|``, ``&``,
    ``U`` / ``R`` (right-associative), then the unary operators. Atoms are names of letters,
    digits, ``_`` and ``.`` other than ``X F G U R true false``; any other name is written
    in double quotes. ``true`` and ``false`` are the constants.

    Parameters
    ----------
    text : str
        The formula.
    notation : {"auto", "prefix", "infix"}, default="auto"
        ``"auto"`` tries prefix first, then infix (the two agree wherever both parse).

    Returns
    -------
    formula : Formula

    Raises
    ------
    ValueError
        With the position of the offending token.

    Examples
    --------
    >>> parse_ltl("->(F(x1),U(!(x0),x1))")
    parse_ltl('->(F(x1),U(!(x0),x1))')
    >>> print(parse_ltl("G(safe) & (b_ok -> F(b)) & (!b U a)").to_prefix())
    &(&(G(safe),->(b_ok,F(b))),U(!(b),a))
    """
    if not isinstance(text, str):
        raise ValueError(f"a formula must be a string, got {type(text).__name__}")
    if notation not in ("auto", "prefix", "infix"):
        raise ValueError(f"notation must be 'auto', 'prefix' or 'infix', got {notation!r}")
    if not text.strip():
        raise ValueError("empty formula")
    errors = []
    for kind in ("prefix", "infix") if notation == "auto" else (notation,):
        parser = _Parser(text)
        try:
            node = parser.prefix() if kind == "prefix" else parser.equivalence()
            parser.done()
            return node
        except ValueError as exc:
            errors.append((kind, exc))
    if len(errors) == 1:
        raise errors[0][1]
    # Commas, and a leading binary operator, only occur in prefix notation: report the
    # error of the likelier reading.
    first = _tokenize(text)[0][1] if _TOKEN.match(text.strip()) else None
    kind, exc = errors[0] if "," in text or first in _BINARY else errors[1]
    raise ValueError(f"cannot parse as prefix or infix LTL; as {kind}: {exc}") from None


# -- the BSI template ---------------------------------------------------------------------


def _conjuncts(formula):
    if isinstance(formula, And):
        return _conjuncts(formula.left) + _conjuncts(formula.right)
    return [formula]


def _literal(formula, prefix):
    """Proposition name a literal stands for, or None when not a literal."""
    negated = False
    while isinstance(formula, Not):
        negated = not negated
        formula = formula.operand
    if not isinstance(formula, Atom):
        return None
    return prefix + formula.name if negated else formula.name


class _NotInTemplate(Exception):
    pass


def _to_specification(formula, names, prefix):
    globals_, eventuals, orders = set(), {}, {}
    conditions = {}  # subtask -> condition (None: unconditioned)

    def set_condition(w, cond):
        if w in conditions and conditions[w] != cond:
            raise _NotInTemplate
        conditions[w] = cond

    def add_global(body):
        for part in _conjuncts(body):
            if isinstance(part, Globally):
                add_global(part.operand)
            elif isinstance(part, Constant):
                if not part.value:
                    raise _NotInTemplate
            else:
                p = _literal(part, prefix)
                if p is None:
                    raise _NotInTemplate
                globals_.add(p)

    def add_clause(part, cond):
        if isinstance(part, Constant) and part.value:
            return
        if isinstance(part, Eventually):
            if isinstance(part.operand, Constant) and part.operand.value:
                return
            w = _literal(part.operand, prefix)
            if w is None:
                raise _NotInTemplate
            set_condition(w, cond)
            eventuals[w] = cond
            return
        if isinstance(part, Until):
            a = _literal(part.right, prefix)
            if a is None:
                raise _NotInTemplate
            if isinstance(part.left, Constant) and part.left.value:
                b = a
            else:
                b = _literal(Not(part.left), prefix)
                if b is None:
                    raise _NotInTemplate
            set_condition(a, cond)
            if a == b:  # (!a U a) = F(a)
                eventuals[a] = cond
            else:
                orders[(a, b)] = cond
            return
        if cond is None and isinstance(part, Implies):
            pi = _literal(part.left, prefix)
            if pi is None:
                raise _NotInTemplate
            for sub in _conjuncts(part.right):
                add_clause(sub, pi)
            return
        if cond is None and isinstance(part, Or):
            for lit, body in ((part.left, part.right), (part.right, part.left)):
                pi = _literal(Not(lit), prefix)
                if pi is not None and isinstance(body, (Eventually, Until)):
                    add_clause(body, pi)
                    return
        raise _NotInTemplate

    try:
        for part in _conjuncts(formula):
            if isinstance(part, Globally):
                add_global(part.operand)
            elif isinstance(part, Constant) and not part.value:
                raise _NotInTemplate
            else:
                add_clause(part, None)
        try:
            closed = Specification(orders=list(orders)).orders
        except ValueError:  # a cycle: a and b must first occur together
            raise _NotInTemplate from None
        # The closure adds (a, c) for a -> b -> c; it is implied only through intermediate
        # subtasks without a condition (their clause holds whatever the trace).
        implied = set()
        succ = {}
        for a, b in orders:
            succ.setdefault(a, set()).add(b)
        for a in succ:
            stack, seen = list(succ[a]), set()
            while stack:
                node = stack.pop()
                if node in seen:
                    continue
                seen.add(node)
                if conditions.get(node) is None:
                    stack.extend(succ.get(node, ()))
            implied.update((a, c) for c in seen)
        if implied != set(closed):
            raise _NotInTemplate
        rename = _renamer(names)
        g = [rename(p) for p in globals_]
        e = [rename(w) for w in eventuals]
        o = [(rename(a), rename(b)) for a, b in orders]
        conds = {rename(w): rename(c) for w, c in conditions.items() if c is not None}
    except _NotInTemplate:
        return None
    return Specification(globals=g, eventuals=e, orders=o, conditions=conds)


def _renamer(names):
    if names is None:
        return lambda p: p
    if isinstance(names, Mapping):
        def rename(p):
            if p not in names:
                raise _NotInTemplate
            return names[p]
        return rename
    if isinstance(names, str):
        raise ValueError("names must be a sequence or a mapping of proposition names")
    table = {}
    for n in names:
        table.setdefault(n if isinstance(n, str) else str(n), n)
    for n in names:
        if isinstance(n, str):
            table[n] = n

    def rename(p):
        if p not in table:
            raise _NotInTemplate
        return table[p]
    return rename
