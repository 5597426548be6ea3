"""The automaton of a specification, built by the project: small clause automata, their product.

Every clause of the template is a small deterministic automaton over the steps of a finite
trace (its truth as :meth:`Specification.satisfied_by` reads it, the last state repeating):

- all ``G(p)`` clauses together: *ok* (accepting) until a step where some ``p`` fails, then
  *dead*;
- ``pi -> F(w)``: at the first step, *free* (accepting) when ``pi`` fails, *done* (accepting)
  when ``w`` holds, else *waiting* until a step with ``w``;
- ``pi_a -> (!b U a)``: at the first step, *free* when ``pi_a`` fails; then *done* at the first
  step with ``a``, *dead* at a step with ``b`` before it.
- a pattern clause (DESIGN §12): its template's minimal DFA
  (:func:`~bsi_sklearn.specification.template_automata.template_dfa`), read through the letter
  bits of the propositions filling its slots; its permanently violated state is its *dead* one.

On a finite trace every clause has one verdict, whether it is read with the last state
repeating (the template's clauses) or as LTLf (pattern clauses): the product accepts when every
component does.

The specification's automaton is their product, explored from the start over the letters (the
assignments of the propositions that matter: one bit for "every global holds", one for each
subtask and condition, then one for each proposition of a pattern clause not among those), and
minimised (Moore's partition refinement). It is exact, needs no
optional package, and takes milliseconds for specifications whose subtasks are ordered; its
size grows as 2^k with k mutually unordered eventual subtasks, as the minimal automaton must
(it has to remember which of them have happened).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from bsi_sklearn.specification.template_automata import VIOLATED, _minimise, template_dfa
from bsi_sklearn.specification.templates import pattern_order

__all__ = ["DFA", "specification_dfa"]

#: Most letter bits (global bit, subtasks, conditions) an automaton is built over.
MAX_LETTER_BITS = 20


@dataclass(frozen=True, eq=False)
class DFA:
    """A deterministic automaton over the letters of a specification's propositions.

    Attributes
    ----------
    globals : tuple
        Propositions of the ``G`` clauses; letter bit 0 says they all hold (when any).
    atoms : tuple
        The propositions read one by one: subtasks and conditions, then the propositions of
        pattern clauses not among them (a global among them too), letter bits after the
        global bit, in this order.
    delta : ndarray of shape (n_states, 2 ** n_bits), int64
        Next state for every state and letter; state 0 is the start.
    accepting : ndarray of shape (n_states,), bool
    """

    globals: tuple
    atoms: tuple
    delta: np.ndarray
    accepting: np.ndarray

    @property
    def n_states(self):
        """Number of states (minimal)."""
        return self.delta.shape[0]

    def letters(self, columns, n_steps):
        """Letter of every step, from ``columns``: identifier -> boolean column.

        Parameters
        ----------
        columns : mapping
            Every proposition of :attr:`globals` and :attr:`atoms` -> its values over time.
        n_steps : int
            Length of the trace.

        Returns
        -------
        letters : ndarray of shape (n_steps,), int64
        """
        bits = []
        if self.globals:
            bits.append(np.logical_and.reduce([np.asarray(columns[p], bool)
                                               for p in self.globals]))
        bits += [np.asarray(columns[a], bool) for a in self.atoms]
        out = np.zeros(n_steps, dtype=np.int64)
        for k, b in enumerate(bits):
            out |= b.astype(np.int64) << k
        return out

    def run(self, letters):
        """The state after reading ``letters`` from the start."""
        state = 0
        for letter in letters:
            state = self.delta[state, letter]
        return int(state)

    def to_dot(self, name="specification"):
        """The automaton in Graphviz DOT: states, accepting ones doubled, labelled edges.

        Parameters
        ----------
        name : str, default="specification"
            The graph's name.

        Returns
        -------
        text : str
        """
        n_bits = len(self.globals) > 0
        names = [" & ".join(map(str, self.globals))] if n_bits else []
        names += [str(a) for a in self.atoms]
        lines = [f"digraph {_quote(name)} {{", "  rankdir=LR;", '  start [shape=point];',
                 "  start -> 0;"]
        for s in range(self.n_states):
            shape = "doublecircle" if self.accepting[s] else "circle"
            lines.append(f"  {s} [shape={shape}];")
        for s in range(self.n_states):
            for target in np.unique(self.delta[s]):
                letters = np.flatnonzero(self.delta[s] == target)
                label = _guard(letters, len(names), names)
                lines.append(f"  {s} -> {int(target)} [label={_quote(label)}];")
        lines.append("}")
        return "\n".join(lines) + "\n"

    def to_hoa(self, name="specification"):
        """The automaton in the Hanoi Omega-Automata format, version 1 (HOA v1).

        The propositions are the ``AP:`` (the globals, then the other atoms, each once; the
        letter bit "every global holds" is their conjunction), every edge has an explicit
        label, and the accepting states are in acceptance set 0 (``Acceptance: 1 Inf(0)``,
        state-based). HOA describes automata over infinite words; this one is read over
        finite words: a finite trace is accepted when its run ends in a state of set 0, as
        the lower-case (informative) header item ``finite-words:`` says.

        Parameters
        ----------
        name : str, default="specification"
            The automaton's ``name:``.

        Returns
        -------
        text : str

        Examples
        --------
        >>> from bsi_sklearn import Specification
        >>> print(specification_dfa(Specification(eventuals=["a"])).to_hoa("F(a)"), end="")
        HOA: v1
        name: "F(a)"
        tool: "bsi-sklearn"
        States: 2
        Start: 0
        AP: 1 "a"
        acc-name: Buchi
        Acceptance: 1 Inf(0)
        properties: trans-labels explicit-labels state-acc deterministic complete
        finite-words: "a finite trace is accepted when its run ends in acceptance set 0"
        --BODY--
        State: 0
        [!0] 0
        [0] 1
        State: 1 {0}
        [t] 1
        --END--
        """
        aps = list(dict.fromkeys([*map(str, self.globals), *map(str, self.atoms)]))
        index = {ap: k for k, ap in enumerate(aps)}
        bits = [" & ".join(str(index[str(g)]) for g in self.globals)] if self.globals else []
        bits += [str(index[str(a)]) for a in self.atoms]
        lines = ["HOA: v1", f"name: {_quote(name)}", 'tool: "bsi-sklearn"',
                 f"States: {self.n_states}", "Start: 0",
                 " ".join([f"AP: {len(aps)}", *map(_quote, aps)]),
                 "acc-name: Buchi", "Acceptance: 1 Inf(0)",
                 "properties: trans-labels explicit-labels state-acc deterministic complete",
                 'finite-words: "a finite trace is accepted when its run ends in acceptance '
                 'set 0"', "--BODY--"]
        for s in range(self.n_states):
            lines.append(f"State: {s}" + (" {0}" if self.accepting[s] else ""))
            for target in np.unique(self.delta[s]):
                label = _guard(np.flatnonzero(self.delta[s] == target), len(bits), bits)
                lines.append(f"[{'t' if label == 'true' else label}] {int(target)}")
        lines.append("--END--")
        return "\n".join(lines) + "\n"


def _quote(text):
    return '"' + str(text).replace("\\", "\\\\").replace('"', '\\"') + '"'


def _guard(letters, n_bits, names):
    """A short sum of products over ``names`` that holds exactly on ``letters``."""
    if len(letters) == 1 << n_bits:
        return "true"
    cubes = {(int(v), (1 << n_bits) - 1) for v in letters}  # (values, care mask)
    while True:  # merge cubes that differ in one cared-for bit (Quine-McCluskey, greedy)
        merged, used = set(), set()
        for a in cubes:
            for b in cubes:
                diff = a[0] ^ b[0]
                if a < b and a[1] == b[1] and diff & a[1] and not diff & (diff - 1):
                    merged.add((a[0] & ~diff, a[1] & ~diff))
                    used |= {a, b}
        if not merged:
            break
        cubes = (cubes - used) | merged
    terms = []
    for values, care in sorted(cubes):
        lits = [("" if values >> k & 1 else "!") + (f"({names[k]})" if " " in names[k]
                                                    else names[k])
                for k in range(n_bits) if care >> k & 1]
        terms.append(" & ".join(lits) if lits else "true")
    return " | ".join(terms)


# ------------------------------------------------------------------ clause automata
# Clause states: 0 start, 1 waiting, 2 accepting sink (done or free), 3 rejecting sink.
_ACCEPT = np.array([False, False, True, False])


def _clause_tables(spec, letters, bit):
    """One (4, n_letters) next-state table per clause, and whether each state accepts."""
    cond = spec.conditions
    tables, accepts = [], []
    n = letters.shape[0]

    def column(ident):
        return letters[:, bit[ident]]

    if spec.globals:
        ok = letters[:, 0]
        table = np.full((4, n), 3)
        table[0] = np.where(ok, 0, 3)
        tables.append(table)
        accepts.append(np.array([True, False, False, False]))
    for w in sorted(spec.eventuals, key=_key):
        hit = column(w)
        free = ~column(cond[w]) if w in cond else np.zeros(n, bool)
        table = np.full((4, n), 2)
        table[0] = np.where(free | hit, 2, 1)
        table[1] = np.where(hit, 2, 1)
        table[3] = 3
        tables.append(table)
        accepts.append(_ACCEPT)
    for a, b in sorted(spec.orders, key=lambda o: (_key(o[0]), _key(o[1]))):
        first, before = column(a), column(b)
        free = ~column(cond[a]) if a in cond else np.zeros(n, bool)
        wait = np.where(first, 2, np.where(before, 3, 1))
        table = np.full((4, n), 2)
        table[0] = np.where(free, 2, wait)
        table[1] = wait
        table[3] = 3
        tables.append(table)
        accepts.append(_ACCEPT)
    for name, props in sorted(spec.patterns, key=pattern_order):
        dfa = template_dfa(name)
        slot_letter = np.zeros(n, dtype=np.int64)
        for i, p in enumerate(props):
            slot_letter |= letters[:, bit[p]].astype(np.int64) << i
        table, accept = dfa.delta[:, slot_letter], dfa.accepting
        if not (dfa.permanence == VIOLATED).any():  # never violated for good: a dead state
            table = np.vstack([table, np.full((1, n), dfa.n_states)])  # of its own, unreached
            accept = np.append(accept, False)
        tables.append(table)
        accepts.append(accept)
    return tables, accepts


def _dead_state(accept, table):
    """A clause's rejecting sink: the non-accepting state that every letter keeps."""
    return next(s for s in range(table.shape[0]) if not accept[s] and (table[s] == s).all())


def _key(x):
    return (type(x).__name__, x)


def specification_dfa(spec):
    """The minimal DFA of ``spec`` (a :class:`~bsi_sklearn.Specification`).

    Parameters
    ----------
    spec : Specification

    Returns
    -------
    dfa : DFA
        Accepts a non-empty trace exactly when ``spec.satisfied_by`` does.

    Raises
    ------
    ValueError
        When the letters would need more than 20 bits (subtasks, conditions, propositions of
        pattern clauses and one bit for the globals).

    Examples
    --------
    >>> from bsi_sklearn import Specification
    >>> dfa = specification_dfa(Specification(globals=["s"], eventuals=["a", "b"],
    ...                                       orders=[("a", "b")]))
    >>> dfa.n_states  # waiting for a, waiting for b, done, dead
    4
    """
    cond = spec.conditions
    atoms = sorted(set(spec.eventuals) | {x for o in spec.orders for x in o}
                   | set(cond.values()), key=_key)
    atoms += sorted({x for _, props in spec.patterns for x in props} - set(atoms), key=_key)
    globals_ = tuple(sorted(spec.globals, key=_key))
    offset = 1 if globals_ else 0
    n_bits = offset + len(atoms)
    if n_bits > MAX_LETTER_BITS:
        raise ValueError(f"the automaton's letters would need {n_bits} bits (more than "
                         f"{MAX_LETTER_BITS}): too many subtasks, conditions and propositions "
                         "of pattern clauses")
    codes = np.arange(1 << n_bits)
    letters = (codes[:, None] >> np.arange(n_bits)) & 1 == 1
    bit = {a: offset + k for k, a in enumerate(atoms)}
    tables, accepts = _clause_tables(spec, letters, bit)
    delta, accepting = _product(tables, accepts, len(codes))
    delta, accepting = _minimise(delta, accepting)
    return DFA(globals_, tuple(atoms), delta, accepting)


def _product(tables, accepts, n_letters):
    """Reachable product states (tuples of clause states) from the all-start state.

    A clause in its rejecting sink rejects for good: every such product state is one (every
    clause in its sink), which keeps the exploration small.
    """
    n_states = max([4] + [t.shape[0] for t in tables])
    table = np.zeros((len(tables), n_states, n_letters), dtype=np.int64)
    for c, t in enumerate(tables):  # rows past a clause's own states are never reached
        table[c, :t.shape[0]] = t
    dead = np.array([_dead_state(acc, t) for acc, t in zip(accepts, tables)], dtype=np.int64)
    clause = np.arange(len(tables))
    start = np.zeros(len(tables), dtype=np.int64)
    index, states, rows = {start.tobytes(): 0}, [start], []
    k = 0
    while k < len(states):
        nxt = np.ascontiguousarray(table[clause, states[k], :].T)  # (n_letters, n_clauses)
        nxt[(nxt == dead).any(axis=1)] = dead
        targets, inverse = np.unique(nxt, axis=0, return_inverse=True)
        ids = np.empty(len(targets), dtype=np.int64)
        for j, row in enumerate(targets):
            key = row.tobytes()
            if key not in index:
                index[key] = len(states)
                states.append(row)
            ids[j] = index[key]
        rows.append(ids[inverse.ravel()])
        k += 1
    accepting = np.array([all(acc[c] for acc, c in zip(accepts, st)) for st in states],
                         dtype=bool)
    return np.array(rows, dtype=np.int64).reshape(len(states), n_letters), accepting
