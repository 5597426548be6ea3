"""LTLf formulas with placeholders evaluated on demonstrations: the user templates' truth.

The tree is :func:`bsi_sklearn.specification.templates.parse_ltlf`'s (the flloat / LTLf2DFA
syntax). :func:`compile_program` flattens it into arrays, children
before parents, and :func:`program_truth` evaluates them on every demonstration with one
backward pass over its steps (a formula's value at ``t`` is a function of its children's at
``t`` and its own at ``t + 1``), in numba. The project's :mod:`bsi_sklearn.ltl` reads ``X`` on
the repeated last state (DESIGN §3); templates need LTLf's strong and weak next, hence this
separate reader.
"""

import numpy as np
from numba import njit

from bsi_sklearn._jit import helper
from bsi_sklearn.specification.templates import OPCODES

__all__ = ["compile_program", "program_truth"]

_ATOM, _TRUE, _FALSE, _NOT, _AND, _OR, _IMPLIES, _EQUIV, _NEXT, _WEAK_NEXT, _EVENTUALLY, \
    _GLOBALLY, _UNTIL, _RELEASE = (OPCODES[k] for k in (
        "atom", "true", "false", "not", "and", "or", "implies", "equiv", "next", "weak_next",
        "eventually", "globally", "until", "release"))


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
