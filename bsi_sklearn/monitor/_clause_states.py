"""The clause states of a growing trace, in numba: each clause slot open, satisfied or violated.

The kernels behind :class:`~bsi_sklearn.monitor.posterior_monitor.PosteriorMonitor` and
:func:`~bsi_sklearn.monitor.posterior_monitor.monitor_traces`: one step read into the clause
states (:func:`_advance`; :func:`_step` checks the step's values first), the trace closed
(:func:`_close`), the states packed into two bit words per clause mask (open, violated) and the
posterior masses of the specifications satisfied, violated and open summed from them
(:func:`_masses`); :func:`_monitor_all` runs whole traces. The rules are the module docstring's
of ``posterior_monitor.py``.

Pattern clauses (DESIGN §12) are global slots after the ``G`` candidates; their columns in the
packed layout are -1. Each instance runs its template's minimal DFA
(:func:`~bsi_sklearn.specification.template_automata.template_dfa`), packed by
:func:`pack_patterns` into one table for every template the roles use: the instance's slot is
violated or satisfied as soon as its DFA state is permanently so, and at the close satisfied
exactly when the state accepts.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit

from bsi_sklearn.model.clauses import clause_index_eventual, clause_index_order, n_clauses
from bsi_sklearn.model.state_layout import split_state
from bsi_sklearn.specification import template_automata
from bsi_sklearn.specification.templates import MAX_SLOTS

OPEN, SATISFIED, VIOLATED = 0, 1, 2
#: The states' names, indexed by their codes.
STATE_NAMES = ("open", "satisfied", "violated")


class PatternTables(NamedTuple):
    """The pattern instances' DFAs, packed for the kernels (one argument).

    Attributes
    ----------
    cols : ndarray of shape (n_patterns, MAX_SLOTS), int64
        Column of each slot of every instance (letter bit ``i`` is slot ``i``); -1 past its
        template's slots.
    delta : ndarray of shape (n_states, 2 ** MAX_SLOTS), int64
        Every used template's transitions, concatenated: a state is a row of this table.
    accepting : ndarray of shape (n_states,), uint8
        Whether a trace ending in the state satisfies its template.
    permanence : ndarray of shape (n_states,), uint8
        The state's clause state: ``OPEN``, or ``SATISFIED`` / ``VIOLATED`` for good.
    start : ndarray of shape (n_patterns,), int64
        Every instance's start row.
    """

    cols: np.ndarray
    delta: np.ndarray
    accepting: np.ndarray
    permanence: np.ndarray
    start: np.ndarray


def pack_patterns(patterns):
    """:class:`PatternTables` of ``patterns``: ``(template name, columns)`` of every instance.

    Each template's DFA is packed once, whatever the number of its instances.
    """
    codes = np.array([OPEN, SATISFIED, VIOLATED], dtype=np.uint8)  # the automata's codes
    width = 1 << MAX_SLOTS
    cols = np.full((len(patterns), MAX_SLOTS), -1, dtype=np.int64)
    start = np.zeros(len(patterns), dtype=np.int64)
    offset, blocks = {}, []
    n_rows = 0
    for k, (name, columns) in enumerate(patterns):
        dfa = template_automata.template_dfa(name)
        if len(columns) != len(dfa.slots):
            raise ValueError(f"pattern candidate {k} ({name!r}) has {len(columns)} columns "
                             f"for {len(dfa.slots)} slots")
        cols[k, :len(columns)] = columns
        if name not in offset:
            offset[name] = n_rows
            blocks.append((dfa, n_rows))
            n_rows += dfa.n_states
        start[k] = offset[name] + dfa.start
    delta = np.zeros((n_rows, width), dtype=np.int64)
    accepting = np.zeros(n_rows, dtype=np.uint8)
    permanence = np.zeros(n_rows, dtype=np.uint8)
    for dfa, at in blocks:
        rows = slice(at, at + dfa.n_states)
        # letters past a template's slots never occur (those bits stay 0): repeat its table
        delta[rows] = np.tile(dfa.delta + at, (1, width // dfa.delta.shape[1]))
        accepting[rows] = dfa.accepting
        permanence[rows] = codes[dfa.permanence]
    return PatternTables(cols, delta, accepting, permanence, start)


@njit(cache=True, nogil=True)
def _step(row, t, state, layout, changed, pat, dfa_state):
    """Advance the clause states by one step; ``-1 - p`` when value ``p`` is not 0/1."""
    for p in range(row.shape[0]):
        if row[p] != 0 and row[p] != 1:
            return -1 - p
    g_idx, s_idx, c_idx = split_state(layout[2:], layout[0], layout[1])
    return _advance(row, t, state, g_idx, s_idx, c_idx, changed, pat, dfa_state)


@njit(cache=True, nogil=True)
def _initial_state(n_g, n):
    state = np.zeros(n_clauses(n_g, n), dtype=np.uint8)
    for a in range(n):
        state[clause_index_order(a, a, n_g, n)] = SATISFIED  # unused diagonal slots
    return state


@njit(cache=True, nogil=True)
def _advance(row, t, state, g_idx, s_idx, c_idx, changed, pat, dfa_state):
    """Read step ``t``; write the slots that changed into ``changed``, return their count.

    ``dfa_state[i]``: the row of pattern instance ``i`` in ``pat.delta`` (global slot
    ``n_g - n_patterns + i``), advanced only while its slot is open.
    """
    n_g, n = g_idx.shape[0], s_idx.shape[0]
    first_pattern = n_g - dfa_state.shape[0]
    k = 0
    for j in range(first_pattern):
        if state[j] == OPEN and row[g_idx[j]] == 0:
            state[j] = VIOLATED
            changed[k] = j
            k += 1
    for i in range(dfa_state.shape[0]):
        j = first_pattern + i
        if state[j] == OPEN:
            letter = 0
            for b in range(pat.cols.shape[1]):
                if pat.cols[i, b] >= 0 and row[pat.cols[i, b]] != 0:
                    letter |= 1 << b
            d = pat.delta[dfa_state[i], letter]
            dfa_state[i] = d
            if pat.permanence[d] != OPEN:
                state[j] = pat.permanence[d]
                changed[k] = j
                k += 1
    for w in range(n):
        c = clause_index_eventual(w, n_g)
        if state[c] == OPEN:
            if (t == 0 and c_idx[w] >= 0 and row[c_idx[w]] == 0) or row[s_idx[w]] != 0:
                state[c] = SATISFIED
                changed[k] = c
                k += 1
    for a in range(n):
        off = t == 0 and c_idx[a] >= 0 and row[c_idx[a]] == 0
        has_a = row[s_idx[a]] != 0
        for b in range(n):
            c = clause_index_order(a, b, n_g, n)
            if state[c] == OPEN:
                if off or has_a:
                    state[c] = SATISFIED
                elif row[s_idx[b]] != 0:
                    state[c] = VIOLATED
                else:
                    continue
                changed[k] = c
                k += 1
    return k


@njit(cache=True, nogil=True)
def _close(state, n_g, changed, pat, dfa_state):
    """Close the trace: open ``G`` clauses satisfied, patterns by their DFA, the rest violated."""
    first_pattern = n_g - dfa_state.shape[0]
    k = 0
    for c in range(state.shape[0]):
        if state[c] == OPEN:
            if c < first_pattern:
                state[c] = SATISFIED
            elif c < n_g:
                state[c] = SATISFIED if pat.accepting[dfa_state[c - first_pattern]] else VIOLATED
            else:
                state[c] = VIOLATED
            changed[k] = c
            k += 1
    return k


@njit(cache=True, nogil=True)
def _pack_states(state, words):
    words[:] = 0
    one = np.uint64(1)
    for c in range(state.shape[0]):
        if state[c] == OPEN:
            words[0, c >> 6] |= one << np.uint64(c & 63)
        elif state[c] == VIOLATED:
            words[1, c >> 6] |= one << np.uint64(c & 63)


@njit(cache=True, nogil=True)
def _masses(masks, probs, words, p):
    # Summed in the order of the specifications, as Posterior.predict_proba sums.
    p_sat = 0.0
    p_viol = 0.0
    p_open = 0.0
    for h in range(masks.shape[0]):
        violated = False
        is_open = False
        for w in range(masks.shape[1]):
            if masks[h, w] & words[1, w]:
                violated = True
                break
            if masks[h, w] & words[0, w]:
                is_open = True
        if violated:
            p_viol += probs[h]
        elif is_open:
            p_open += probs[h]
        else:
            p_sat += probs[h]
    p[0] = min(max(p_sat, 0.0), 1.0)
    p[1] = p_viol
    p[2] = p_open


@njit(cache=True, nogil=True)
def _monitor_all(data, offsets, g_idx, s_idx, c_idx, masks, probs, pat):
    n_g, n = g_idx.shape[0], s_idx.shape[0]
    out = np.empty((data.shape[0], 3))
    changed = np.empty(n_clauses(n_g, n), dtype=np.int64)
    words = np.zeros((2, masks.shape[1]), dtype=np.uint64)
    p = np.zeros(3)
    _pack_states(_initial_state(n_g, n), words)
    _masses(masks, probs, words, p)
    p0 = p.copy()
    for i in range(offsets.shape[0] - 1):
        state = _initial_state(n_g, n)
        dfa_state = pat.start.copy()
        for t in range(offsets[i + 1] - offsets[i]):
            r = offsets[i] + t
            k = _advance(data[r], t, state, g_idx, s_idx, c_idx, changed, pat, dfa_state)
            if t == 0:
                p[:] = p0
            if k > 0:
                _pack_states(state, words)
                _masses(masks, probs, words, p)
            out[r, 0] = p[0]
            out[r, 1] = p[1]
            out[r, 2] = p[2]
    return out
