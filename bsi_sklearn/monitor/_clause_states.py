"""The clause states of a growing trace, in numba: each clause slot open, satisfied or violated.

The kernels behind :class:`~bsi_sklearn.monitor.posterior_monitor.PosteriorMonitor` and
:func:`~bsi_sklearn.monitor.posterior_monitor.monitor_traces`: one step read into the clause
states (:func:`_advance`; :func:`_step` checks the step's values first), the trace closed
(:func:`_close`), the states packed into two bit words per clause mask (open, violated) and the
posterior masses of the specifications satisfied, violated and open summed from them
(:func:`_masses`); :func:`_monitor_all` runs whole traces. The rules are the module docstring's
of ``posterior_monitor.py``.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from bsi_sklearn.model.clauses import clause_index_eventual, clause_index_order, n_clauses
from bsi_sklearn.model.state_layout import split_state

OPEN, SATISFIED, VIOLATED = 0, 1, 2
#: The states' names, indexed by their codes.
STATE_NAMES = ("open", "satisfied", "violated")


@njit(cache=True, nogil=True)
def _step(row, t, state, layout, changed):
    """Advance the clause states by one step; ``-1 - p`` when value ``p`` is not 0/1."""
    for p in range(row.shape[0]):
        if row[p] != 0 and row[p] != 1:
            return -1 - p
    g_idx, s_idx, c_idx = split_state(layout[2:], layout[0], layout[1])
    return _advance(row, t, state, g_idx, s_idx, c_idx, changed)


@njit(cache=True, nogil=True)
def _initial_state(n_g, n):
    state = np.zeros(n_clauses(n_g, n), dtype=np.uint8)
    for a in range(n):
        state[clause_index_order(a, a, n_g, n)] = SATISFIED  # unused diagonal slots
    return state


@njit(cache=True, nogil=True)
def _advance(row, t, state, g_idx, s_idx, c_idx, changed):
    """Read step ``t``; write the slots that changed into ``changed``, return their count."""
    n_g, n = g_idx.shape[0], s_idx.shape[0]
    k = 0
    for j in range(n_g):
        if state[j] == OPEN and row[g_idx[j]] == 0:
            state[j] = VIOLATED
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
def _close(state, n_g, changed):
    k = 0
    for c in range(state.shape[0]):
        if state[c] == OPEN:
            state[c] = SATISFIED if c < n_g else VIOLATED
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
def _monitor_all(data, offsets, g_idx, s_idx, c_idx, masks, probs):
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
        for t in range(offsets[i + 1] - offsets[i]):
            r = offsets[i] + t
            k = _advance(data[r], t, state, g_idx, s_idx, c_idx, changed)
            if t == 0:
                p[:] = p0
            if k > 0:
                _pack_states(state, words)
                _masses(masks, probs, words, p)
            out[r, 0] = p[0]
            out[r, 1] = p[1]
            out[r, 2] = p[2]
    return out
