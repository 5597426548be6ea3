"""LTLf text with placeholders, read and evaluated: the user templates of the pattern library.

:func:`parse_ltlf` reads the flloat / LTLf2DFA syntax (``!``, ``&``, ``|``, ``->``, ``<->``,
``X`` strong next, ``WX`` weak next, ``F``, ``G``, ``U``, ``R``, ``true``, ``false``; every
other name is a placeholder). :func:`compile_program` flattens the tree into arrays, children
before parents, and :func:`program_truth` evaluates them on every demonstration with one
backward pass over its steps (a formula's value at ``t`` is a function of its children's at
``t`` and its own at ``t + 1``), in numba. The project's :mod:`bsi_sklearn.ltl` reads ``X`` on
the repeated last state (DESIGN §3); templates need LTLf's strong and weak next, hence this
separate reader.
"""

import re

import numpy as np
from numba import njit

from bsi_sklearn._jit import helper

__all__ = ["parse_ltlf", "placeholders", "compile_program", "program_truth"]

_ATOM, _TRUE, _FALSE, _NOT, _AND, _OR, _IMPLIES, _EQUIV = range(8)
_NEXT, _WEAK_NEXT, _EVENTUALLY, _GLOBALLY, _UNTIL, _RELEASE = range(8, 14)
_UNARY = {"!": _NOT, "X": _NEXT, "WX": _WEAK_NEXT, "F": _EVENTUALLY, "G": _GLOBALLY}
_BINARY = {"&": _AND, "|": _OR, "->": _IMPLIES, "<->": _EQUIV, "U": _UNTIL, "R": _RELEASE}
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


def compile_program(tree, slots):
    """Arrays ``(ops, left, right, slot)``, one entry a distinct subformula, children first.

    ``slot[k]`` is the placeholder's index in ``slots`` for an atom (else -1); ``left`` /
    ``right`` index earlier entries (-1 where unused). The last entry is the formula.
    """
    index, ops, left, right, slot = {}, [], [], [], []

    def emit(node):
        if node in index:
            return index[node]
        kids = [emit(child) for child in node[1:]] if node[0] != _ATOM else []
        ops.append(node[0])
        left.append(kids[0] if kids else -1)
        right.append(kids[1] if len(kids) > 1 else -1)
        slot.append(slots.index(node[1]) if node[0] == _ATOM else -1)
        index[node] = len(ops) - 1
        return index[node]

    emit(tree)
    return tuple(np.array(v, dtype=np.int64) for v in (ops, left, right, slot))


def program_truth(program, data, offsets, cols, out):
    """Truth of the program's formula at step 0 of every demonstration, for every instance.

    ``cols[k]`` holds instance ``k``'s column for each slot; ``out`` (n_demos, n_instances)
    uint8 is filled in place.
    """
    ops, left, right, slot = program
    _program_truth(ops, left, right, slot, data, offsets, cols, out,
                   np.zeros((2, ops.shape[0]), dtype=np.uint8))


@njit(cache=True, nogil=True)
def _program_truth(ops, left, right, slot, data, offsets, cols, out, buf):
    # buf's two rows take turns as this step's values and the next step's (no copying).
    n_nodes = ops.shape[0]
    for k in range(cols.shape[0]):
        for i in range(offsets.shape[0] - 1):
            s, e = offsets[i], offsets[i + 1]
            for t in range(e - 1, s - 1, -1):
                cur, nxt = buf[t & 1], buf[(t + 1) & 1]
                last = t == e - 1
                for j in range(n_nodes):
                    atom = data[t, cols[k, slot[j]]] != 0 if slot[j] >= 0 else False
                    cur[j] = _node(ops[j], j, left[j], right[j], cur, nxt, last, atom)
            out[i, k] = buf[s & 1, n_nodes - 1]


@helper
def _node(op, j, a, b, cur, nxt, last, atom):  # noqa: C901 - one branch per operator
    # Node j at step t: its children's values at t are in cur (computed first), its own
    # value at t + 1 in nxt (unread at the last step).
    if op == _ATOM:
        return 1 if atom else 0
    if op == _TRUE:
        return 1
    if op == _FALSE:
        return 0
    if op == _NOT:
        return 1 - cur[a]
    if op == _AND:
        return cur[a] & cur[b]
    if op == _OR:
        return cur[a] | cur[b]
    if op == _IMPLIES:
        return (1 - cur[a]) | cur[b]
    if op == _EQUIV:
        return 1 if cur[a] == cur[b] else 0
    if op == _NEXT:  # strong next: false at the last step
        return 0 if last else nxt[a]
    if op == _WEAK_NEXT:  # weak next: true at the last step
        return 1 if last else nxt[a]
    if op == _EVENTUALLY:
        return 1 if cur[a] else (0 if last else nxt[j])
    if op == _GLOBALLY:
        return 0 if cur[a] == 0 else (1 if last else nxt[j])
    if op == _UNTIL:
        return 1 if cur[b] else (0 if last or cur[a] == 0 else nxt[j])
    # release, a R b = !(!a U !b): b now, and a now, or the end, or a R b from the next step
    return 0 if cur[b] == 0 else (1 if cur[a] or last else nxt[j])
