"""The minimal DFA of a pattern template (DESIGN §12), built by LTLf progression.

A template with ``k`` slots is read over letters that assign its slots: letter ``L`` has bit
``i`` set when slot ``i`` holds at the step (``2 ** k`` letters). :func:`template_dfa` builds
the minimal complete DFA accepting exactly the non-empty finite traces that satisfy the
template at step 0 (LTLf: ``X`` strong, ``WX`` weak, ``U`` strong), and classifies its states
for the three-valued monitor (DESIGN §10): a state is *permanently satisfied* when every state
reachable from it accepts, *permanently violated* when none does, else *open*.

Construction. The formula is put in negation normal form (``!X f`` is ``WX !f``, ``!F f`` is
``G !f``, ``!(f U g)`` is ``!f R !g``), then progressed through the letters: after reading a
prefix, the residual is what the rest of the trace must satisfy, a positive Boolean
combination of obligations ``Ne(f)`` ("the rest is non-empty and satisfies ``f``": what
``X f``, ``F`` and ``U`` leave) and ``We(f)`` ("the rest is empty or satisfies ``f``": what
``WX f``, ``G`` and ``R`` leave). The rest of a trace that ends here is empty, so a residual
accepts when it is true with every ``Ne`` false and every ``We`` true. A positive Boolean
function has one irredundant DNF (its minimal terms), which is the residual's canonical form:
the obligations are wrapped subformulas, finitely many, so the states are too. Moore's
partition refinement then merges the residuals with the same future.
"""

from __future__ import annotations

from functools import lru_cache
from typing import NamedTuple

import numpy as np

from bsi_sklearn.specification.templates import OPCODES, get_template, parse_ltlf

__all__ = ["TemplateDFA", "template_dfa", "OPEN", "SATISFIED", "VIOLATED", "PERMANENCE_NAMES"]

#: Permanence codes of :attr:`TemplateDFA.permanence` (the monitor's clause-state codes).
OPEN, SATISFIED, VIOLATED = 0, 1, 2
#: The permanence codes' names, indexed by code.
PERMANENCE_NAMES = ("open", "satisfied", "violated")

_ATOM, _TRUE, _FALSE = OPCODES["atom"], OPCODES["true"], OPCODES["false"]
_NOT, _AND, _OR = OPCODES["not"], OPCODES["and"], OPCODES["or"]
_IMPLIES, _EQUIV = OPCODES["implies"], OPCODES["equiv"]
_NEXT, _WEAK_NEXT = OPCODES["next"], OPCODES["weak_next"]
_EVENTUALLY, _GLOBALLY = OPCODES["eventually"], OPCODES["globally"]
_UNTIL, _RELEASE = OPCODES["until"], OPCODES["release"]
# Negation normal form adds one node kind: a negated slot.
_NOT_ATOM = -1
# Obligations on the rest of the trace: (kind, nnf formula).
_NE, _WE = 0, 1
# Residuals: frozensets of terms, each a frozenset of obligations (their AND).
_R_TRUE = frozenset([frozenset()])
_R_FALSE = frozenset()


class TemplateDFA(NamedTuple):
    """The minimal DFA of a template over its slots' letters.

    Attributes
    ----------
    slots : tuple of str
        The template's placeholders; slot ``i`` is letter bit ``i``.
    delta : ndarray of shape (n_states, 2 ** n_slots), int64
        Next state for every state and letter.
    accepting : ndarray of shape (n_states,), bool
        Whether a trace whose run ends in the state satisfies the template.
    permanence : ndarray of shape (n_states,), int8
        :data:`OPEN`, :data:`SATISFIED` (every reachable state accepts) or :data:`VIOLATED`
        (no reachable state accepts).
    start : int
        The state before any step (0; it rejects: a trace is not empty).
    """

    slots: tuple
    delta: np.ndarray
    accepting: np.ndarray
    permanence: np.ndarray
    start: int

    @property
    def n_states(self):
        """Number of states (minimal)."""
        return self.delta.shape[0]

    def run(self, letters, state=None):
        """The state after reading ``letters`` (slot assignments) from ``state`` (the start)."""
        state = self.start if state is None else state
        for letter in letters:
            state = self.delta[state, letter]
        return int(state)

    def accepts(self, letters):
        """Whether the template holds on the non-empty trace of ``letters``."""
        return bool(self.accepting[self.run(letters)]) if len(letters) else False


def template_dfa(template):
    """The minimal DFA of a catalogue template or an LTLf template text (cached).

    Parameters
    ----------
    template : str or Template
        A catalogue name (``"Response"``), LTLf text with placeholders, or a
        :class:`~bsi_sklearn.specification.templates.Template`.

    Returns
    -------
    dfa : TemplateDFA
        Its arrays are read-only (shared by every caller).

    Raises
    ------
    ValueError
        As :func:`~bsi_sklearn.specification.templates.get_template` does.

    Examples
    --------
    >>> dfa = template_dfa("Response")  # G(a -> F(b)); letter bit 0: a, bit 1: b
    >>> dfa.n_states, dfa.accepts([0b01]), dfa.accepts([0b01, 0b10])
    (3, False, True)
    >>> [PERMANENCE_NAMES[c] for c in template_dfa("Absence").permanence]
    ['open', 'open', 'violated']
    """
    t = get_template(template)
    return _build(t.formula, t.slots)


@lru_cache(maxsize=None)
def _build(formula, slots):
    slot_of = {name: i for i, name in enumerate(slots)}
    n_letters = 1 << len(slots)
    start = frozenset([frozenset([(_NE, _nnf(parse_ltlf(formula), False))])])
    index, states, rows = {start: 0}, [start], []
    k = 0
    while k < len(states):
        row = []
        for letter in range(n_letters):
            nxt = _step(states[k], letter, slot_of)
            if nxt not in index:
                index[nxt] = len(states)
                states.append(nxt)
            row.append(index[nxt])
        rows.append(row)
        k += 1
    delta = np.array(rows, dtype=np.int64).reshape(len(states), n_letters)
    accepting = np.array([_accepts_empty(r) for r in states], dtype=bool)
    delta, accepting = _minimise(delta, accepting)
    permanence = _permanence(delta, accepting)
    for a in (delta, accepting, permanence):
        a.setflags(write=False)
    return TemplateDFA(tuple(slots), delta, accepting, permanence, 0)


# ------------------------------------------------------------------ formulas
def _nnf(node, negated):
    """The negation normal form of a parsed tree (``negated``: of its negation)."""
    op = node[0]
    if op == _ATOM:
        return (_NOT_ATOM, node[1]) if negated else node
    if op in (_TRUE, _FALSE):
        return ((_FALSE,) if op == _TRUE else (_TRUE,)) if negated else node
    if op == _NOT:
        return _nnf(node[1], not negated)
    if op == _IMPLIES:  # x -> y is !x | y
        return _nnf((_OR, (_NOT, node[1]), node[2]), negated)
    if op == _EQUIV:  # x <-> y is (x & y) | (!x & !y)
        x, y = node[1], node[2]
        return _nnf((_OR, (_AND, x, y), (_AND, (_NOT, x), (_NOT, y))), negated)
    dual = {_AND: _OR, _OR: _AND, _NEXT: _WEAK_NEXT, _WEAK_NEXT: _NEXT,
            _EVENTUALLY: _GLOBALLY, _GLOBALLY: _EVENTUALLY, _UNTIL: _RELEASE, _RELEASE: _UNTIL}
    if op not in dual:
        raise ValueError(f"unknown operator code {op} in a template's tree")
    return ((dual[op] if negated else op),) + tuple(_nnf(c, negated) for c in node[1:])


def _and(x, y):
    return _absorb(frozenset(a | b for a in x for b in y))


def _or(x, y):
    return _absorb(x | y)


def _absorb(terms):
    """The minimal terms: a term with a proper subset among the terms is implied by it."""
    return frozenset(t for t in terms if not any(u < t for u in terms))


def _obligation(kind, f):
    # Ne(true) stays an obligation (the trace must go on); We(true) and Ne(false) need none.
    if f[0] == _TRUE and kind == _WE:
        return _R_TRUE
    if f[0] == _FALSE and kind == _NE:
        return _R_FALSE
    return frozenset([frozenset([(kind, f)])])


@lru_cache(maxsize=None)
def _progress(f, letter, slot_items):
    """The residual of NNF formula ``f`` read at a step with ``letter``."""
    op = f[0]
    if op in (_ATOM, _NOT_ATOM):
        holds = bool(letter >> dict(slot_items)[f[1]] & 1)
        return _R_TRUE if holds == (op == _ATOM) else _R_FALSE
    if op == _TRUE:
        return _R_TRUE
    if op == _FALSE:
        return _R_FALSE
    if op == _AND:
        return _and(_progress(f[1], letter, slot_items), _progress(f[2], letter, slot_items))
    if op == _OR:
        return _or(_progress(f[1], letter, slot_items), _progress(f[2], letter, slot_items))
    if op == _NEXT:
        return _obligation(_NE, f[1])
    if op == _WEAK_NEXT:
        return _obligation(_WE, f[1])
    if op == _EVENTUALLY:  # f now, or a later step that has f
        return _or(_progress(f[1], letter, slot_items), _obligation(_NE, f))
    if op == _GLOBALLY:  # f now, and f at every later step there is
        return _and(_progress(f[1], letter, slot_items), _obligation(_WE, f))
    if op == _UNTIL:  # g now, or f now and (f U g) from a next step that exists
        now = _progress(f[1], letter, slot_items)
        return _or(_progress(f[2], letter, slot_items), _and(now, _obligation(_NE, f)))
    if op == _RELEASE:  # g now, and f now or (f R g) from the next step if any
        now = _progress(f[1], letter, slot_items)
        return _and(_progress(f[2], letter, slot_items), _or(now, _obligation(_WE, f)))
    raise ValueError(f"unknown operator code {op} in a template's tree")


def _step(residual, letter, slot_of):
    """The residual after one more step: each obligation's formula progressed through it."""
    items = tuple(sorted(slot_of.items()))
    out = _R_FALSE
    for term in residual:
        acc = _R_TRUE
        for _, f in term:  # the rest is non-empty now: Ne(f) and We(f) both need f here
            acc = _and(acc, _progress(f, letter, items))
            if not acc:
                break
        out = _or(out, acc)
    return out


def _accepts_empty(residual):
    """The residual's value on the empty rest: ``Ne`` false, ``We`` true."""
    return any(all(kind == _WE for kind, _ in term) for term in residual)


# ------------------------------------------------------------------ automata
def _minimise(delta, accepting):
    """Moore's partition refinement; the start stays state 0, the others in order reached."""
    classes = accepting.astype(np.int64)
    n_classes = len(np.unique(classes))
    while True:
        signature = np.concatenate([classes[:, None], classes[delta]], axis=1)
        _, classes = np.unique(signature, axis=0, return_inverse=True)
        classes = classes.ravel()
        if len(np.unique(classes)) == n_classes:
            break
        n_classes = len(np.unique(classes))
    _, first = np.unique(classes, return_index=True)
    rank = np.empty(len(first), dtype=np.int64)
    rank[np.argsort(first)] = np.arange(len(first))
    reps = np.sort(first)
    return rank[classes][delta[reps]], accepting[reps]


def _permanence(delta, accepting):
    """Each state's permanence code, from the states reachable from it (itself included)."""
    n = delta.shape[0]
    reach = np.eye(n, dtype=bool)
    reach[np.repeat(np.arange(n), delta.shape[1]), delta.ravel()] = True
    while True:  # transitive closure by squaring; a handful of states
        more = (reach.astype(np.int64) @ reach.astype(np.int64)) > 0
        if (more == reach).all():
            break
        reach = more
    out = np.full(n, OPEN, dtype=np.int8)
    out[(reach <= accepting[None, :]).all(axis=1)] = SATISFIED
    out[~(reach & accepting[None, :]).any(axis=1)] = VIOLATED
    return out
