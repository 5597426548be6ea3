"""Gibbs-within-MCMC sampler over (tau, W1, order structure), in numba.

Each step picks one coordinate uniformly: an inclusion bit of tau or W1 (Gibbs flip), or a
subtask whose place in the order structure is redrawn among *all* places it could go (Gibbs
re-insertion), each candidate weighted by prior x likelihood. Every move is an exact Gibbs update
of its block, so no Hastings ratio is needed; together they reach every hypothesis.

The sampler keeps, per (deduplicated) demonstration, the number of clauses of the current
hypothesis it violates; a demonstration satisfies the hypothesis when that count is zero. Traces
are never read: only the precomputed clause-truth matrix is.
"""

from typing import NamedTuple

import numpy as np
from numba import carray, njit
from numba.core import types
from numba.extending import intrinsic

from bsi_sklearn.inference._gibbs_moves import (
    add_pair,
    chain_move,
    flip_move,
    forest_move,
    sat_counts,
)
from bsi_sklearn.likelihood import log_likelihood
from bsi_sklearn.model import Model
from bsi_sklearn.priors import (
    draw_hypothesis,
    log_inclusion,
    log_prior,
    log_prior_structure,
    log_prior_subset,
)

__all__ = ["Demos", "run_chain", "deduplicate_demos", "score_states", "unique_states"]


class Demos(NamedTuple):
    """Deduplicated clause truth, clause-major, with the labels as weights."""

    truth_t: np.ndarray   # (n_clauses, n_unique) uint8
    w_pos: np.ndarray     # (n_unique,) float64: acceptable demonstrations behind each row
    w_neg: np.ndarray     # (n_unique,) float64: unacceptable ones
    n_pos: float          # w_pos.sum()
    n_neg: float          # w_neg.sum()


class ChainState(NamedTuple):
    """The current hypothesis of a chain: inclusion bits of tau and W1, the parent array."""

    tau: np.ndarray       # (n_g,) int64
    w1: np.ndarray        # (n,) int64
    parent: np.ndarray    # (n,) int64


class ChainBuffers(NamedTuple):
    """Scratch space of one chain, allocated once by :func:`run_chain`."""

    ubuf: np.ndarray      # uniforms, refilled in bulk
    viol: np.ndarray      # (D,) int32: clauses of the current hypothesis each row violates
    cur: np.ndarray       # (D,) int32: the same for a candidate
    lw: np.ndarray        # candidate log weights (prior + likelihood)
    cand_lp: np.ndarray   # candidate log priors
    cand_head: np.ndarray
    cand_pos: np.ndarray
    cand_ew: np.ndarray   # exponentiated weights
    child: np.ndarray     # (n,) chain successor (Priors 1, 2)
    in_s: np.ndarray      # (n,) membership of the pruned subtree (Prior 3)
    cost: np.ndarray      # (n, D) violations added by an ancestor of the subtree (Prior 3)
    size: np.ndarray      # (n,) subtree sizes (Prior 3)
    old_parent: np.ndarray


def unique_states(states, counts, return_inverse=False):
    """Unique state rows (sorted canonically) and the number of samples of each.

    With ``return_inverse``, also the index of every input row among the unique rows.
    """
    if len(states) == 0 or states.shape[1] == 0:
        # Zero-width rows (empty template): every sample is the same hypothesis.
        out = states[:1], np.array([int(np.sum(counts))], dtype=np.int64)[: len(states[:1])]
        return (*out, np.zeros(len(states), dtype=np.int64)) if return_inverse else out
    # Rows of small ints: shift to non-negative and pack into one integer key when they fit.
    shifted = states.astype(np.int64) + 1
    bits = max(int(shifted.max()).bit_length(), 1)
    if bits * states.shape[1] <= 63:
        weights = np.left_shift(1, bits * np.arange(states.shape[1] - 1, -1, -1))
        keys = shifted @ weights
        _, first, inverse = np.unique(keys, return_index=True, return_inverse=True)
    else:
        _, first, inverse = np.unique(states, axis=0, return_index=True, return_inverse=True)
    inverse = inverse.ravel()
    total = np.bincount(inverse, weights=counts, minlength=len(first))
    out = states[first], total.astype(np.int64)
    return (*out, inverse) if return_inverse else out


def deduplicate_demos(truth, y01):
    """Collapse demonstrations with identical clause-truth rows into weighted unique rows.

    Returns
    -------
    Demos
        ``truth_t`` (n_clauses, n_unique) uint8, the transposed unique rows (clause-major for
        the kernel's inner loops); ``w_pos`` / ``w_neg`` (n_unique,) float64, the numbers of
        acceptable / unacceptable demonstrations behind every unique row; their sums.
    """
    rows, inverse = np.unique(truth, axis=0, return_inverse=True)
    inverse = inverse.ravel()
    w_pos = np.bincount(inverse, weights=(y01 == 1).astype(float), minlength=len(rows))
    w_neg = np.bincount(inverse, weights=(y01 == 0).astype(float), minlength=len(rows))
    # Whole-number weights: their sums are exact in any order.
    return Demos(np.ascontiguousarray(rows.T), np.ascontiguousarray(w_pos, dtype=np.float64),
                 np.ascontiguousarray(w_neg, dtype=np.float64), float(w_pos.sum()),
                 float(w_neg.sum()))


@intrinsic
def _data_pointer(typingctx, arr):
    # The raw data pointer of a contiguous array.
    def codegen(context, builder, signature, args):
        return context.make_array(signature.args[0])(context, builder, args[0]).data

    return types.CPointer(arr.dtype)(arr), codegen


@njit(cache=True, nogil=True)
def _unmanaged(a):
    """A view of contiguous ``a`` without a reference count (no NRT meminfo).

    Passing a managed array to a non-inlined jitted function costs an atomic increment and
    decrement of its reference count; the chain kernel makes hundreds of such calls per sweep,
    and those atomics took about 65% of its time. Views are only valid while ``a`` is alive:
    the kernel takes them of buffers its Python caller owns for the whole call.
    """
    return carray(_data_pointer(a), a.shape)


@njit(cache=True, nogil=True)
def _unmanaged_bundles(state, demos, model, bufs):
    # The same bundles made of unmanaged views (see _unmanaged).
    state = ChainState(_unmanaged(state.tau), _unmanaged(state.w1), _unmanaged(state.parent))
    demos = Demos(_unmanaged(demos.truth_t), _unmanaged(demos.w_pos), _unmanaged(demos.w_neg),
                  demos.n_pos, demos.n_neg)
    model = Model(model.n_g, model.n, model.prior, model.forest, model.p_global,
                  model.p_eventual, model.p_part, model.n_new, model.log_eps, model.likelihood,
                  _unmanaged(model.lp_chains), _unmanaged(model.forest_g), model.forest_const)
    bufs = ChainBuffers(_unmanaged(bufs.ubuf), _unmanaged(bufs.viol), _unmanaged(bufs.cur),
                        _unmanaged(bufs.lw), _unmanaged(bufs.cand_lp),
                        _unmanaged(bufs.cand_head), _unmanaged(bufs.cand_pos),
                        _unmanaged(bufs.cand_ew), _unmanaged(bufs.child), _unmanaged(bufs.in_s),
                        _unmanaged(bufs.cost), _unmanaged(bufs.size),
                        _unmanaged(bufs.old_parent))
    return state, demos, model, bufs


@njit(cache=True, nogil=True)
def _init_viol(tau, w1, parent, truth_t, model):
    # int32 counts (not int64): twice as many lanes in the kernels' vectorised loops.
    viol = np.zeros(truth_t.shape[1], dtype=np.int32)
    return viol, _fill_viol(viol, tau, w1, parent, truth_t, model)


@njit(cache=True, nogil=True)
def _fill_viol(viol, tau, w1, parent, truth_t, model):
    # Per demonstration, the number of clauses of the hypothesis it violates; returns N.
    n_g, n = model.n_g, model.n
    viol[:] = 0
    n_conj = 0
    for j in range(n_g):
        if tau[j]:
            add_pair(viol, truth_t, j, 1)
            n_conj += 1
    for w in range(n):
        if w1[w]:
            add_pair(viol, truth_t, n_g + w, 1)
            n_conj += 1
    for v in range(n):
        a = parent[v]
        while a >= 0:
            add_pair(viol, truth_t, n_g + n + a * n + v, 1)
            n_conj += 1
            a = parent[a]
    return n_conj


@njit(cache=True, nogil=True)
def _chain_kernel(state, demos, model, bufs, rng, n_sweeps, burn_in):
    # One sweep updates every coordinate once (tau bits, W1 bits, every subtask's place);
    # the state is recorded after each sweep past burn-in. The state and the scratch buffers
    # (allocated by run_chain) are used through unmanaged views: see _unmanaged.
    state, demos, model, bufs = _unmanaged_bundles(state, demos, model, bufs)
    tau, w1, parent = state.tau, state.w1, state.parent
    truth_t, viol, old_parent = demos.truth_t, bufs.viol, bufs.old_parent
    n_g, n = model.n_g, model.n
    # Uniforms come from a buffer refilled in bulk (the same stream as one rng.random() per
    # draw), so that the generator, a managed object, is not passed to every move.
    ubuf = bufs.ubuf
    n_u = ubuf.shape[0]
    upos = n_u
    n_conj = _fill_viol(viol, tau, w1, parent, truth_t, model)
    n_keep = n_sweeps - burn_in
    states = np.empty((n_keep, n_g + 2 * n), dtype=np.int16)
    trace_lp = np.empty(n_keep)
    lg_in, lg_out = log_inclusion(model.p_global)
    le_in, le_out = log_inclusion(model.p_eventual)
    lp_sub = (log_prior_subset(tau.sum(), n_g, model.p_global)
              + log_prior_subset(w1.sum(), n, model.p_eventual))
    lp_struct = log_prior_structure(parent, model)
    ps, ns = sat_counts(viol, demos.w_pos, demos.w_neg)
    ll = log_likelihood(ps, ns, demos.n_pos, demos.n_neg, n_conj, model.log_eps,
                        model.likelihood)
    moved = 0
    updates = 0
    counts = np.zeros(n_keep, dtype=np.int64)
    k = -1
    last_moved = -1
    for sweep in range(n_sweeps):
        # A sweep uses at most one uniform per coordinate: top the buffer up first.
        if upos + n_g + 2 * n > n_u:
            rest = n_u - upos
            ubuf[:rest] = ubuf[upos:]
            ubuf[rest:] = rng.random(n_u - rest)
            upos = 0
        for j in range(n_g):
            new, ll, used = flip_move(j, tau[j], lg_in, lg_out, viol, n_conj, demos, model,
                                       ubuf[upos])
            upos += used
            if new != tau[j]:
                n_conj += 1 if new else -1
                lp_sub += (lg_in - lg_out) if new else (lg_out - lg_in)
                tau[j] = new
                moved += 1
        for w in range(n):
            new, ll, used = flip_move(n_g + w, w1[w], le_in, le_out, viol, n_conj, demos,
                                       model, ubuf[upos])
            upos += used
            if new != w1[w]:
                n_conj += 1 if new else -1
                lp_sub += (le_in - le_out) if new else (le_out - le_in)
                w1[w] = new
                moved += 1
        updates += n_g + n
        if n > 1:
            for v in range(n):
                old_parent[:] = parent
                if model.forest:
                    n_conj, lp_struct, ll = forest_move(v, parent, viol, n_conj, demos, model,
                                                         bufs, ubuf[upos])
                else:
                    n_conj, lp_struct, ll = chain_move(v, parent, viol, n_conj, demos, model,
                                                        bufs, ubuf[upos])
                upos += 1  # a structure move always draws
                for u in range(n):
                    if parent[u] != old_parent[u]:
                        moved += 1
                        break
            updates += n
        if sweep >= burn_in:
            r = sweep - burn_in
            trace_lp[r] = lp_sub + lp_struct + ll
            if k >= 0 and moved == last_moved:
                counts[k] += 1  # run-length: the state did not change during this sweep
                continue
            k += 1
            last_moved = moved
            counts[k] = 1
            for j in range(n_g):
                states[k, j] = tau[j]
            for w in range(n):
                states[k, n_g + w] = w1[w]
                states[k, n_g + n + w] = parent[w]
    return states[:k + 1], counts[:k + 1], trace_lp, moved / max(updates, 1), updates


def run_chain(seed, demos, model, n_samples, burn_in):
    """Run one chain from a prior draw.

    Parameters
    ----------
    seed : int
        Seed of the chain's ``numpy.random.Generator`` (prior draw and every move).
    demos : Demos
        Deduplicated clause truth and label weights (:func:`deduplicate_demos`).
    model : Model
        The model bundle (:func:`bsi_sklearn.model.make_model`).
    n_samples, burn_in : int
        Sweeps recorded, and sweeps discarded first.

    Returns
    -------
    states : ndarray of int16
        The recorded states, run-length encoded: rows ``[tau (n_g), w1 (n), parent (n)]``.
    counts : ndarray of int64
        How many consecutive samples each row stands for.
    trace_lp : ndarray
        The log posterior after every recorded sweep.
    move_rate : float
        Fraction of coordinate updates that changed the state.
    n_updates : int
        Number of coordinate updates (a sample is one sweep: every coordinate once).
    """
    rng = np.random.default_rng(seed)
    tau, w1, parent = draw_hypothesis(model, rng)
    n_g, n = model.n_g, model.n
    # The kernel's state and scratch buffers live here, for the whole call (see _unmanaged).
    state = ChainState(np.ascontiguousarray(tau, dtype=np.int64),
                       np.ascontiguousarray(w1, dtype=np.int64),
                       np.ascontiguousarray(parent, dtype=np.int64))
    D = demos.truth_t.shape[1]
    k = 2 * n + 2  # the most candidate places of one structure move
    bufs = ChainBuffers(
        ubuf=np.empty(max(1024, 2 * (n_g + 2 * n))),
        viol=np.zeros(D, dtype=np.int32), cur=np.empty(D, dtype=np.int32),
        lw=np.empty(k), cand_lp=np.empty(k),
        cand_head=np.empty(k, dtype=np.int64), cand_pos=np.empty(k, dtype=np.int64),
        cand_ew=np.empty(k),
        child=np.empty(n, dtype=np.int64), in_s=np.zeros(n, dtype=np.int64),
        cost=np.zeros((n, D), dtype=np.int32),
        size=np.empty(n, dtype=np.int64), old_parent=np.empty(n, dtype=np.int64),
    )
    return _chain_kernel(state, demos, model, bufs, rng, burn_in + n_samples, burn_in)


@njit(cache=True, nogil=True)
def score_states(states, demos, model):
    """Exact unnormalised log posterior of every state row."""
    n_g, n = model.n_g, model.n
    out = np.empty(states.shape[0])
    for r in range(states.shape[0]):
        tau = states[r, :n_g].astype(np.int64)
        w1 = states[r, n_g:n_g + n].astype(np.int64)
        parent = states[r, n_g + n:].astype(np.int64)
        viol, n_conj = _init_viol(tau, w1, parent, demos.truth_t, model)
        ps, ns = sat_counts(viol, demos.w_pos, demos.w_neg)
        out[r] = log_prior(tau, w1, parent, model) + log_likelihood(
            ps, ns, demos.n_pos, demos.n_neg, n_conj, model.log_eps, model.likelihood)
    return out
