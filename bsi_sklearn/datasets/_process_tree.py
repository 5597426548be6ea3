"""Random process trees, their simulation and the perturbation of cases (for ``process_logs``).

A tree is nested tuples: ``(LEAF, i)`` (activity ``i``), ``(SEQ, children)``, ``(XOR,
children)``, ``(AND, children)`` (interleaving), ``(LOOP, body, redo)``, ``(OPT, child)``.
Every random number comes from :class:`Uniforms`, a stream of ``Generator.random`` doubles read
in order, so a seed gives the same cases on every machine (PCG64 and its doubles are fixed by
NumPy, no floating-point arithmetic decides a branch except comparisons and products by
integers).
"""

from __future__ import annotations

__all__ = ["LEAF", "SEQ", "XOR", "AND", "LOOP", "OPT", "Uniforms", "draw_tree", "simulate",
           "perturb", "tree_text", "P_REDO", "MAX_REDO", "P_SKIP_OPTIONAL", "P_DEVIATE",
           "P_SECOND_OP", "P_TARGETED"]

LEAF, SEQ, XOR, AND, LOOP, OPT = range(6)
_NAMES = {SEQ: "->", XOR: "X", AND: "+", LOOP: "*", OPT: "?"}

#: Operator of an inner node of :func:`draw_tree`, with these probabilities.
_OPERATORS = (SEQ, XOR, AND, LOOP)
_OPERATOR_P = (0.55, 0.2, 0.15, 0.1)
#: A leaf is optional with this probability.
_P_OPTIONAL_LEAF = 0.1
#: A loop repeats (redo, then body again) with this probability, at most ``MAX_REDO`` times.
P_REDO = 0.35
MAX_REDO = 3
#: An optional step is skipped with this probability.
P_SKIP_OPTIONAL = 0.5
#: A case deviates from the process with this probability (one operation, a second one with
#: ``P_SECOND_OP``); an operation concerns one of the rule's activities with ``P_TARGETED``.
P_DEVIATE = 0.8
P_SECOND_OP = 0.5
P_TARGETED = 0.8


class Uniforms:
    """Doubles in [0, 1) from a ``numpy.random.Generator``, read one at a time (in chunks)."""

    def __init__(self, rng, chunk=1 << 15):
        self.rng = rng
        self.chunk = int(chunk)
        self.buf = []
        self.i = 0

    def __call__(self):
        """The next double."""
        if self.i == len(self.buf):
            self.buf = self.rng.random(self.chunk).tolist()
            self.i = 0
        value = self.buf[self.i]
        self.i += 1
        return value

    def below(self, n):
        """An integer uniform in ``[0, n)``."""
        return min(int(self() * n), n - 1)


def _pick(u, probabilities):
    r, acc = u(), 0.0
    for k, p in enumerate(probabilities):
        acc += p
        if r < acc:
            return k
    return len(probabilities) - 1


def draw_tree(activities, u):
    """A random process tree whose leaves are ``activities`` (indices), each exactly once.

    An inner node is a sequence (0.55), an exclusive choice (0.2), a parallel block (0.15) or
    a loop (0.1) over 2 to 4 contiguous groups of its activities (a loop: a body and a redo
    part); a leaf is optional with probability 0.1.
    """
    acts = list(activities)
    if len(acts) == 1:
        leaf = (LEAF, acts[0])
        return (OPT, leaf) if u() < _P_OPTIONAL_LEAF else leaf
    op = _OPERATORS[_pick(u, _OPERATOR_P)]
    k = 2 if op == LOOP else 2 + u.below(min(4, len(acts)) - 1)
    cuts = sorted(_sample_cuts(len(acts) - 1, k - 1, u))
    groups = [acts[a:b] for a, b in zip([0, *cuts], [*cuts, len(acts)])]
    children = tuple(draw_tree(g, u) for g in groups)
    if op == LOOP:
        return (LOOP, children[0], children[1])
    return (op, children)


def _sample_cuts(n, k, u):
    """``k`` distinct cut positions among ``1..n``."""
    pool = list(range(1, n + 1))
    out = []
    for _ in range(k):
        out.append(pool.pop(u.below(len(pool))))
    return out


def simulate(tree, u):
    """One case: the activity indices of a run of ``tree``, in order."""
    out = []
    _walk(tree, u, out)
    return out


def _walk(node, u, out):
    op = node[0]
    if op == LEAF:
        out.append(node[1])
    elif op == SEQ:
        for child in node[1]:
            _walk(child, u, out)
    elif op == XOR:
        _walk(node[1][u.below(len(node[1]))], u, out)
    elif op == OPT:
        if u() >= P_SKIP_OPTIONAL:
            _walk(node[1], u, out)
    elif op == LOOP:
        _walk(node[1], u, out)
        n = 0
        while n < MAX_REDO and u() < P_REDO:
            _walk(node[2], u, out)
            _walk(node[1], u, out)
            n += 1
    else:  # AND: the children's runs interleaved, every interleaving equally likely
        runs = []
        for child in node[1]:
            run = []
            _walk(child, u, run)
            if run:
                runs.append(run)
        _interleave(runs, u, out)


def _interleave(runs, u, out):
    left = [len(r) for r in runs]
    pos = [0] * len(runs)
    total = sum(left)
    while total:
        r = u.below(total)
        k = 0
        while r >= left[k]:
            r -= left[k]
            k += 1
        out.append(runs[k][pos[k]])
        pos[k] += 1
        left[k] -= 1
        total -= 1


def perturb(case, targets, n_activities, u):
    """A case after a deviation (with probability ``P_DEVIATE``), or the case itself.

    One operation (two with ``P_SECOND_OP``), each a skip (an event removed), a move (an
    event taken out and put back at another position: a step done out of order) or an insert
    (an activity performed once more, at a random position), equally likely. With
    ``P_TARGETED`` the operation concerns one of ``targets`` (the rule's activities: an
    occurrence of it is skipped or moved, or it is inserted), else any event or activity.
    """
    if u() >= P_DEVIATE:
        return case
    case = list(case)
    for _ in range(2 if u() < P_SECOND_OP else 1):
        kind = u.below(3)
        activity = targets[u.below(len(targets))] if u() < P_TARGETED else None
        if kind == 2:  # insert
            if activity is None:
                activity = u.below(n_activities)
            case.insert(u.below(len(case) + 1), activity)
            continue
        where = [i for i, a in enumerate(case) if a == activity] if activity is not None \
            else list(range(len(case)))
        if not where or len(case) == 1:  # nothing to skip or move; a case keeps one event
            continue
        i = where[u.below(len(where))]
        event = case.pop(i)
        if kind == 1:  # move
            case.insert(u.below(len(case) + 1), event)
    return case


def tree_text(node, names):
    """The tree in the process-tree notation of the literature: ``->(a, X(b, c))``."""
    op = node[0]
    if op == LEAF:
        return names[node[1]]
    if op == OPT:
        return f"?({tree_text(node[1], names)})"
    children = node[1:] if op == LOOP else node[1]
    return f"{_NAMES[op]}(" + ", ".join(tree_text(c, names) for c in children) + ")"
