"""The LTL formula tree: ``Formula`` and its nodes, their rendering and per-node semantics."""

from __future__ import annotations

import re
from dataclasses import dataclass

import numpy as np

from bsi_sklearn.data.traces import check_traces
from bsi_sklearn.ltl.evaluation import evaluate_traces

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
]


class Formula:
    """Base class of LTL formulas over named propositions (immutable, hashable).

    Semantics on finite traces: a formula is evaluated at ``t = 0`` on the infinite
    word made of the finite trace whose **last state repeats forever**. Hence ``G p`` holds
    when ``p`` holds at every step, ``F p`` when it holds at some step, ``a U b`` when some
    step has ``b`` and every earlier step has ``a``, and ``X phi`` at the last step reads
    ``phi`` on the (repeated) last state. For formulas without ``X`` this coincides with
    the usual LTLf semantics; on the last step ``X`` differs from LTLf's strong next (false
    there) and weak next (true there). A pattern clause, ``Response(a, b)``
    (:class:`~bsi_sklearn.ltl.pattern.Pattern`), is the exception: its template is read in
    LTLf on the finite trace.

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
    >>> from bsi_sklearn.ltl import parse_ltl
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
            Any format accepted by :func:`bsi_sklearn.data.traces.check_traces` (list of
            ``(T_i, n_props)`` arrays or DataFrames, 3-D array, 2-D array of length-one
            traces).
        feature_names : sequence of str, default=None
            Proposition names of the columns; taken from the DataFrame columns when omitted.
            Atoms whose name is a decimal integer (``"3"``) that is not a column name read
            that column index.

        Returns
        -------
        satisfied : ndarray of shape (n_demos,), dtype bool
        """
        traces = check_traces(X, estimator_name="Formula.evaluate")
        return evaluate_traces(self, traces, feature_names)

    def satisfied_by(self, trace, feature_names=None):
        """Truth of the formula at ``t = 0`` on one trace ``(T, n_props)`` (array or frame)."""
        return bool(self.evaluate([trace], feature_names=feature_names)[0])

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
        ``(!b U a)`` and ``pi -> (!b U a)`` clauses over propositions (see
        :class:`~bsi_sklearn.specification.Specification`), and pattern clauses
        (:class:`~bsi_sklearn.ltl.pattern.Pattern`, ``Response(a, b)``) as conjuncts of their own.
        Literals are read as propositions: ``!p`` becomes the proposition named
        ``negation_prefix + p`` (the column
        :class:`~bsi_sklearn.data.preprocessing.NegationAugmenter` adds), so ``G(!p)`` is in the
        template through ``G("!p")`` and ``(p U a)`` through ``(!"!p" U a)``. ``G`` distributes
        over ``&``; ``true U a`` and ``!a U a`` read as ``F(a)``; ``l | C`` reads as ``!l -> C``.

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
        >>> from bsi_sklearn.ltl import parse_ltl
        >>> parse_ltl("&(G(x0),F(x1))").to_specification()
        Specification(globals=['x0'], eventuals=['x1'], orders=[])
        >>> parse_ltl("G(!(x0))").to_specification(names=["x0", "!x0"])
        Specification(globals=['!x0'], eventuals=[], orders=[])
        >>> parse_ltl("G(!(x0))").to_specification(names=["x0"]) is None
        True
        >>> parse_ltl("F(&(a,F(b)))").to_specification() is None
        True
        """
        from bsi_sklearn.ltl.template import formula_to_specification

        return formula_to_specification(self, names, negation_prefix)


def _as_formula(value):
    if isinstance(value, Formula):
        return value
    if isinstance(value, bool):
        return Constant(value)
    if isinstance(value, str):
        from bsi_sklearn.ltl.parser import parse_ltl

        return parse_ltl(value)
    raise TypeError(f"cannot combine a formula with {type(value).__name__}")


# Names an atom may have without quotes; the others are written in double quotes.
_CONSTANTS = {"true": True, "false": False}
_RESERVED = {"X", "F", "G", "U", "R"}
_PLAIN_NAME = re.compile(r"[A-Za-z0-9_][A-Za-z0-9_.]*")


def _quote(name):
    plain = _PLAIN_NAME.fullmatch(name) and name not in _RESERVED and name.lower() not in (
        _CONSTANTS
    )
    return name if plain else f'"{name}"'


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
