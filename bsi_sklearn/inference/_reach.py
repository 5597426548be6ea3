"""What a chain has weighed: the states it visited and their one-block neighbours.

A Gibbs update of a block (one global bit; one subtask's place in the order structure with its
eventual bit, :mod:`bsi_sklearn.inference._gibbs_moves`) weighs, exactly, every state that
differs from the current one in that block, and draws among them. A chain sitting at a state
has therefore weighed all of its one-block neighbours: had one of them carried much more mass,
the chain would have moved there. Where the posterior is a plateau of many equally probable
states (interchangeable subtasks in the order structure, common on event logs), each chain
visits only part of it in a few hundred sweeps, but weighs nearly all of it; the missed mass
per chain (its warning, and the agreement ``n_samples="auto"`` waits for) asks whether the
chains *reached* the same states (visited, or one block from a visited one), not whether each
visited every one.

:func:`reach` computes, among given states (the chains' union), the states each chain reached.
Two states are one block apart exactly when they are equal once that block is taken out: a
global bit set to 0; a subtask's eventual bit set to 0 and the subtask spliced out of its chain
(Priors 1 and 2) or cut from its parent with its subtree (Prior 3). Equal keys are found by
sorting a 64-bit hash of the states with the block taken out, and every match is confirmed
entry by entry, so a hash collision can never join two states.
"""

import numpy as np
from numba import njit

from bsi_sklearn._jit import helper
from bsi_sklearn.model.priors import is_forest
from bsi_sklearn.model.state_layout import parent_offset, w1_offset

__all__ = ["reach", "visited_shares"]

# Fixed odd multipliers of the hash (one per entry), so that the result never depends on a
# random draw; the confirmation makes them a matter of speed only.
_HASH_SEED = 0x5EED_B51


def reach(states, model, visits):
    """The states each chain reached: visited, or one block from a state it visited.

    Parameters
    ----------
    states : ndarray of shape (n_states, n_g + 2 n)
        Distinct state rows ``[tau | W1 | parent]`` (the chains' union).
    model : Model
        Its ``n_g`` and ``n``, and its prior: whether structures are forests
        (:func:`~bsi_sklearn.model.priors.is_forest`).
    visits : sequence of ndarray of int
        For each chain, the indices into ``states`` of the states it visited.

    Returns
    -------
    reached : list of ndarray of int
        For each chain, the indices of the states it visited or that are one block from one it
        visited.

    Examples
    --------
    >>> import numpy as np
    >>> from bsi_sklearn.model import make_model
    >>> m = make_model(prior="sets_of_chains", likelihood="cb", n_globals=2, n_subtasks=1)
    >>> rows = np.array([[0, 0, 0, -1], [1, 0, 0, -1], [1, 0, 1, -1]])
    >>> [r.tolist() for r in reach(rows, m, [np.array([0])])]  # row 2: a bit and F(0) away
    [[0, 1]]
    """
    states = np.ascontiguousarray(states, dtype=np.int64)
    n_states = len(states)
    visited = np.zeros((len(visits), n_states), dtype=np.bool_)
    for k, rows in enumerate(visits):
        visited[k, np.asarray(rows, dtype=np.int64)] = True
    reached = visited.copy()
    if n_states > 1 and states.shape[1] > 0:
        mult = (np.random.default_rng(_HASH_SEED).integers(
            0, 2**62, size=states.shape[1], dtype=np.int64).astype(np.uint64) * np.uint64(2)
            + np.uint64(1))
        _reach(states, int(model.n_g), int(model.n), bool(is_forest(model)), mult, visited,
               reached, np.empty(n_states, dtype=np.uint64),
               np.empty((2, states.shape[1]), np.int64),
               np.empty((n_states, max(model.n, 1)), dtype=np.int64))
    return [np.flatnonzero(r) for r in reached]


@helper
def _masked(row, b, n_g, n, forest, child, out):
    # ``row`` with block b taken out, into ``out``: b < n_g a global bit set to 0; else subtask
    # v = b - n_g with its eventual bit set to 0, cut from its parent (a forest: its subtree
    # goes with it) or spliced out of its chain (its child takes its parent).
    for j in range(row.shape[0]):
        out[j] = row[j]
    if b < n_g:
        out[b] = 0
        return
    v = b - n_g
    base = parent_offset(n_g, n)
    out[w1_offset(n_g) + v] = 0
    if not forest:
        c = child[v]
        if c >= 0:
            out[base + c] = row[base + v]
    out[base + v] = -1


@helper
def _key(row, h, b, n_g, n, forest, child, mult):
    # The hash of ``_masked(row, b)`` from the row's own hash ``h``: only the (at most three)
    # entries the block's removal changes are taken out and put back.
    if b < n_g:
        return h - np.uint64(row[b] + 2) * mult[b] + np.uint64(2) * mult[b]
    v = b - n_g
    base = parent_offset(n_g, n)
    e = w1_offset(n_g) + v
    h = h - np.uint64(row[e] + 2) * mult[e] + np.uint64(2) * mult[e]
    if not forest:
        c = child[v]
        if c >= 0:
            h = h - np.uint64(row[base + c] + 2) * mult[base + c] \
                + np.uint64(row[base + v] + 2) * mult[base + c]
    return h - np.uint64(row[base + v] + 2) * mult[base + v] + np.uint64(1) * mult[base + v]


@helper
def _varies(states, child, b, n_g, n):
    # Whether two states can differ in block b alone. A global bit: when it is not the same
    # in every state. A subtask: two states one block apart differ in its eventual bit, its
    # parent or its child (else, it being spliced out alike, they would be equal).
    if b < n_g:
        for s in range(1, states.shape[0]):
            if states[s, b] != states[0, b]:
                return True
        return False
    v = b - n_g
    e, p = w1_offset(n_g) + v, parent_offset(n_g, n) + v
    for s in range(1, states.shape[0]):
        if states[s, e] != states[0, e] or states[s, p] != states[0, p] \
                or child[s, v] != child[0, v]:
            return True
    return False


@njit(cache=True, nogil=True)
def _reach(states, n_g, n, forest, mult, visited, reached, keys, scratch, child):
    n_states = states.shape[0]
    base = parent_offset(n_g, n)
    # The child of every subtask in every state (chains have at most one), and every state's
    # hash.
    hashes = np.empty(n_states, dtype=np.uint64)
    for s in range(n_states):
        for v in range(n):
            child[s, v] = -1
        for u in range(n):
            p = states[s, base + u]
            if p >= 0:
                child[s, p] = u
        h = np.uint64(0)
        for j in range(states.shape[1]):
            h += np.uint64(states[s, j] + 2) * mult[j]
        hashes[s] = h
    members = np.empty(n_states, dtype=np.int64)
    for b in range(n_g + n):
        if not _varies(states, child, b, n_g, n):
            continue
        for s in range(n_states):
            keys[s] = _key(states[s], hashes[s], b, n_g, n, forest, child[s], mult)
        order = np.argsort(keys)
        i = 0
        while i < n_states:
            j = i + 1
            while j < n_states and keys[order[j]] == keys[order[i]]:
                j += 1
            if j - i > 1:
                _join(states, order[i:j], b, (n_g, n, forest), child, visited, reached,
                      scratch, members)
            i = j


@helper
def _join(states, run, b, layout, child, visited, reached, scratch, members):
    # The states of ``run`` share a hash key with block b out; every one equal (block b out)
    # to the first not yet grouped forms a group of one-block neighbours with it, and a chain
    # that visited a member of a group reached all of it. Groups are taken in turn until the
    # run is used up (more than one group only on a hash collision). layout: (n_g, n, forest).
    n_g, n, forest = layout
    done = np.zeros(run.shape[0], dtype=np.bool_)
    for a in range(run.shape[0]):
        if done[a]:
            continue
        _masked(states[run[a]], b, n_g, n, forest, child[run[a]], scratch[0])
        m = 0
        for c in range(a, run.shape[0]):
            if done[c]:
                continue
            _masked(states[run[c]], b, n_g, n, forest, child[run[c]], scratch[1])
            equal = True
            for e in range(scratch.shape[1]):
                if scratch[0, e] != scratch[1, e]:
                    equal = False
                    break
            if equal:
                done[c] = True
                members[m] = run[c]
                m += 1
        for k in range(visited.shape[0]):
            hit = False
            for i in range(m):
                if visited[k, members[i]]:
                    hit = True
                    break
            if hit:
                for i in range(m):
                    reached[k, members[i]] = True


def visited_shares(visited, visited_lp, model, per_chain):
    """What each chain reached among the visited states, and their restricted posterior.

    Without the closure: each chain's share is what :func:`reach` gives (indices into the
    visited states), and the posterior the exact one restricted to them, normalised.
    """
    probs = np.exp(visited_lp - visited_lp.max())
    return reach(visited, model, per_chain), probs / probs.sum()
