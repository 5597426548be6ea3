"""Parsing LTL text in the prefix notation of samples2LTL / Scarlet or in infix notation."""

from __future__ import annotations

import re

from bsi_sklearn.ltl.formula import (
    _CONSTANTS,
    _RESERVED,
    And,
    Atom,
    Constant,
    Equivalent,
    Eventually,
    Globally,
    Implies,
    Next,
    Not,
    Or,
    Release,
    Until,
)
from bsi_sklearn.ltl.pattern import Pattern

__all__ = ["parse_ltl"]

_UNARY = {"!": Not, "~": Not, "X": Next, "F": Eventually, "G": Globally}
_BINARY = {"&": And, "|": Or, "->": Implies, "<->": Equivalent, "U": Until, "R": Release}

_TOKEN = re.compile(
    r"(?:(?P<op><->|->|[!~&|(),])|(?P<name>[A-Za-z0-9_][A-Za-z0-9_.]*)"
    r"|\"(?P<quoted>[^\"]+)\"|\{(?P<template>[^{}]*)\})"
)


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
        elif m.group("template") is not None:  # a user template's LTLf text, in braces
            tokens.append(("template", m.group("template"), pos))
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

    def pattern(self, kind, tok, argument):
        """A pattern clause ``Name(args)`` / ``{ltlf}(args)``, or None for anything else."""
        if not (kind == "template" or (kind == "name" and tok not in _RESERVED
                                       and tok.lower() not in _CONSTANTS
                                       and self.peek()[:2] == ("op", "("))):
            return None
        at = self.i - 1
        self.take("(")
        args = [argument()]
        while self.peek()[1] == ",":
            self.take(",")
            args.append(argument())
        self.take(")")
        try:
            return Pattern(tok, tuple(args))
        except ValueError as exc:
            self.i = at
            raise self.error(str(exc)) from None

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
        node = self.pattern(kind, tok, self.prefix) or self.leaf(kind, tok)
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
        node = self.pattern(kind, tok, self.equivalence) or self.leaf(kind, tok)
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
    in double quotes. ``true`` and ``false`` are the constants. A pattern clause
    (:class:`~bsi_sklearn.ltl.pattern.Pattern`, read in LTLf) is a template's name and its
    propositions, ``Response(a, b)``, or a user template's LTLf text in braces,
    ``{G(x -> WX(!x))}(a)``: the forms :meth:`Specification.to_ltl` writes.

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
    >>> print(parse_ltl("Response(order, pay) & {G(x -> WX(!x))}(refund)"))
    Response(order, pay) & {G(x -> WX(!x))}(refund)
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
