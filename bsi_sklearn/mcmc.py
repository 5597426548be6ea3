"""Gibbs-within-MCMC sampler over (tau, W1, order structure), in numba.

Each step picks one coordinate uniformly: an inclusion bit of tau or W1 (Gibbs flip), or a
subtask whose place in the order structure is redrawn among *all* places it could go (Gibbs
re-insertion), each candidate weighted by prior x likelihood. Every move is an exact Gibbs update
of its block, so no Hastings ratio is needed; together they reach every hypothesis.

The sampler keeps, per (deduplicated) demonstration, the number of clauses of the current
hypothesis it violates; a demonstration satisfies the hypothesis when that count is zero. Traces
are never read: only the precomputed clause-truth matrix is.
"""

import math
from typing import NamedTuple

import numpy as np
from numba import carray, njit
from numba.core import types
from numba.extending import intrinsic

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


def unique_states(states, counts):
    """Unique state rows (sorted canonically) and the number of samples of each."""
    if len(states) == 0 or states.shape[1] == 0:
        # Zero-width rows (empty template): every sample is the same hypothesis.
        return states[:1], np.array([int(np.sum(counts))], dtype=np.int64)[: len(states[:1])]
    # Rows of small ints: shift to non-negative and pack into one integer key when they fit.
    shifted = states.astype(np.int64) + 1
    bits = max(int(shifted.max()).bit_length(), 1)
    if bits * states.shape[1] <= 63:
        weights = np.left_shift(1, bits * np.arange(states.shape[1] - 1, -1, -1))
        keys = shifted @ weights
        _, first, inverse = np.unique(keys, return_index=True, return_inverse=True)
    else:
        _, first, inverse = np.unique(states, axis=0, return_index=True, return_inverse=True)
    total = np.bincount(inverse.ravel(), weights=counts, minlength=len(first))
    return states[first], total.astype(np.int64)


def deduplicate_demos(truth, y01):
    """Collapse demonstrations with identical clause-truth rows into weighted unique rows.

    Returns
    -------
    truth_t : ndarray (n_clauses, n_unique) uint8
        Transposed unique rows (clause-major for the kernel's inner loops).
    w_pos, w_neg : ndarray (n_unique,) float64
        Numbers of acceptable / unacceptable demonstrations behind every unique row.
    """
    rows, inverse = np.unique(truth, axis=0, return_inverse=True)
    inverse = inverse.ravel()
    w_pos = np.bincount(inverse, weights=(y01 == 1).astype(float), minlength=len(rows))
    w_neg = np.bincount(inverse, weights=(y01 == 0).astype(float), minlength=len(rows))
    return np.ascontiguousarray(rows.T), w_pos, w_neg


def make_demos(truth_t, w_pos, w_neg):
    """The :class:`Demos` bundle of :func:`deduplicate_demos`'s output."""
    w_pos = np.ascontiguousarray(w_pos, dtype=np.float64)
    w_neg = np.ascontiguousarray(w_neg, dtype=np.float64)
    # Whole-number weights: their sum is exact in any order.
    return Demos(np.ascontiguousarray(truth_t), w_pos, w_neg, float(w_pos.sum()),
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


# The weights are whole numbers (demonstration counts), so their sums are exact in any order:
# letting LLVM reassociate them (SIMD reductions) cannot change a result.
_SUMS = {"reassoc"}


@njit(cache=True, nogil=True, fastmath=_SUMS)
def _sat_counts(viol, w_pos, w_neg):
    ps = 0.0
    ns = 0.0
    for d in range(viol.shape[0]):
        ok = viol[d] == 0
        ps += w_pos[d] if ok else 0.0
        ns += w_neg[d] if ok else 0.0
    return ps, ns


@njit(cache=True, nogil=True, fastmath=_SUMS)
def _flip_sums(viol, truth_t, c, inc, w_pos, w_neg):
    # Weighted counts of demonstrations satisfying the hypothesis without / with clause c.
    ps_out = 0.0
    ns_out = 0.0
    ps_in = 0.0
    ns_in = 0.0
    for d in range(viol.shape[0]):
        t = truth_t[c, d]
        ok = viol[d] - (inc if t == 0 else 0) == 0
        both = ok and t != 0
        ps_out += w_pos[d] if ok else 0.0
        ns_out += w_neg[d] if ok else 0.0
        ps_in += w_pos[d] if both else 0.0
        ns_in += w_neg[d] if both else 0.0
    return ps_out, ns_out, ps_in, ns_in


@njit(cache=True, nogil=True)
def _draw(lw, k, u, ew):
    # Sample index i < k with probability proportional to exp(lw[i]), from a uniform u in
    # [0, 1); ew is scratch space (each weight is exponentiated once).
    mx = -np.inf
    for i in range(k):
        if lw[i] > mx:
            mx = lw[i]
    total = 0.0
    for i in range(k):
        ew[i] = math.exp(lw[i] - mx)
        total += ew[i]
    u = u * total
    acc = 0.0
    for i in range(k):
        acc += ew[i]
        if u < acc:
            return i
    # Fall back to the last candidate with non-zero weight (rounding at the top end).
    for i in range(k - 1, -1, -1):
        if lw[i] > -np.inf:
            return i
    return k - 1


@njit(cache=True, nogil=True)
def _add_pair(viol, truth_t, c, sign):
    for d in range(viol.shape[0]):
        viol[d] += sign if truth_t[c, d] == 0 else 0


@njit(cache=True, nogil=True)
def _flip_move(c, inc, lp_in, lp_out, viol, n_conj, demos, model, u):
    # Gibbs update of one inclusion bit: returns the new bit, the new log-likelihood and
    # whether the uniform u was used (only when both outcomes are possible).
    truth_t = demos.truth_t
    ps_out, ns_out, ps_in, ns_in = _flip_sums(viol, truth_t, c, inc, demos.w_pos, demos.w_neg)
    n_out = n_conj - inc
    ll_out = log_likelihood(ps_out, ns_out, demos.n_pos, demos.n_neg, n_out, model.log_eps,
                            model.likelihood)
    ll_in = log_likelihood(ps_in, ns_in, demos.n_pos, demos.n_neg, n_out + 1, model.log_eps,
                           model.likelihood)
    lw_out = lp_out + ll_out
    lw_in = lp_in + ll_in
    # P(in) = 1 / (1 + exp(lw_out - lw_in)), computed without overflow.
    used = 0
    if lw_in == -np.inf:
        new = 0
    elif lw_out == -np.inf:
        new = 1
    else:
        diff = lw_out - lw_in
        p_in = 1.0 / (1.0 + math.exp(diff)) if diff < 700.0 else 0.0
        new = 1 if u < p_in else 0
        used = 1
    if new != inc:
        _add_pair(viol, truth_t, c, 1 if new else -1)
    return new, (ll_in if new else ll_out), used


@njit(cache=True, nogil=True)
def _chain_move(v, parent, viol, n_conj, demos, model, bufs, unif):
    # Priors 1 / 2: take v out of its chain and redraw its place among every position of every
    # remaining chain and a new chain (a candidate only where the prior has such structures).
    # Returns (n_conj, log prior of the structure, log-likelihood) of the new state.
    truth_t, w_pos, w_neg = demos.truth_t, demos.w_pos, demos.w_neg
    n_pos, n_neg = demos.n_pos, demos.n_neg
    n = model.n
    base = model.n_g + n
    log_eps, lik_code, lp_chains = model.log_eps, model.likelihood, model.lp_chains
    cur, lw, cand_lp, cand_ew = bufs.cur, bufs.lw, bufs.cand_lp, bufs.cand_ew
    cand_head, cand_pos, child = bufs.cand_head, bufs.cand_pos, bufs.child
    D = viol.shape[0]
    child[:] = -1
    for u in range(n):
        if parent[u] >= 0:
            child[parent[u]] = u
    # Remove v's pairs: (ancestor, v) and (v, descendant).
    a = parent[v]
    while a >= 0:
        _add_pair(viol, truth_t, base + a * n + v, -1)
        n_conj -= 1
        a = parent[a]
    d_ = child[v]
    while d_ >= 0:
        _add_pair(viol, truth_t, base + v * n + d_, -1)
        n_conj -= 1
        d_ = child[d_]
    if child[v] >= 0:
        parent[child[v]] = parent[v]
    if parent[v] >= 0:
        child[parent[v]] = child[v]
    parent[v] = -1
    child[v] = -1
    # Candidates: every position of every remaining chain, plus a new chain.
    k = 0
    m_rem = 0
    for h in range(n):
        if h == v or parent[h] >= 0:
            continue
        m_rem += 1
    for h in range(n):
        if h == v or parent[h] >= 0:
            continue
        L = 0
        u = h
        for d in range(D):
            cur[d] = viol[d]
        while u >= 0:
            c = base + v * n + u
            for d in range(D):
                cur[d] += 1 if truth_t[c, d] == 0 else 0
            L += 1
            u = child[u]
        m_new = m_rem
        lp = lp_chains[m_new]
        u = h
        for p in range(L + 1):
            ps, ns = _sat_counts(cur, w_pos, w_neg)
            cand_lp[k] = lp
            lw[k] = lp + log_likelihood(ps, ns, n_pos, n_neg, n_conj + L, log_eps, lik_code)
            cand_head[k] = h
            cand_pos[k] = p
            k += 1
            if u >= 0:
                ca = base + u * n + v
                cb = base + v * n + u
                for d in range(D):
                    cur[d] += (truth_t[cb, d] != 0) - (truth_t[ca, d] != 0)
                u = child[u]
    if lp_chains[m_rem + 1] > -np.inf or k == 0:
        ps, ns = _sat_counts(viol, w_pos, w_neg)
        cand_lp[k] = lp_chains[m_rem + 1]
        lw[k] = cand_lp[k] + log_likelihood(ps, ns, n_pos, n_neg, n_conj, log_eps, lik_code)
        cand_head[k] = -1
        cand_pos[k] = 0
        k += 1
    j = _draw(lw, k, unif, cand_ew)
    h = cand_head[j]
    if h < 0:
        return n_conj, cand_lp[j], lw[j] - cand_lp[j]
    p = cand_pos[j]
    u = h
    prev = -1
    i = 0
    while u >= 0:
        if i < p:
            _add_pair(viol, truth_t, base + u * n + v, 1)
        else:
            _add_pair(viol, truth_t, base + v * n + u, 1)
        n_conj += 1
        if i == p - 1:
            prev = u
        i += 1
        u = child[u]
    # Splice v in after prev (or at the head).
    nxt = h if prev < 0 else child[prev]
    parent[v] = prev
    if nxt >= 0:
        parent[nxt] = v
    return n_conj, cand_lp[j], lw[j] - cand_lp[j]


@njit(cache=True, nogil=True)
def _forest_move(v, parent, viol, n_conj, demos, model, bufs, unif):
    # Prior 3: prune the subtree rooted at v and regraft it anywhere outside it.
    truth_t, w_pos, w_neg = demos.truth_t, demos.w_pos, demos.w_neg
    n_pos, n_neg = demos.n_pos, demos.n_neg
    n = model.n
    base = model.n_g + n
    log_eps, lik_code = model.log_eps, model.likelihood
    g, g_const = model.forest_g, model.forest_const
    cur, lw, cand_lp, cand_ew = bufs.cur, bufs.lw, bufs.cand_lp, bufs.cand_ew
    cand_head, in_s, cost, size = bufs.cand_head, bufs.in_s, bufs.cost, bufs.size
    D = viol.shape[0]
    size_s = 0
    for u in range(n):
        a = u
        while a >= 0 and a != v:
            a = parent[a]
        in_s[u] = 1 if a == v else 0
        size_s += in_s[u]
    # Remove (ancestor of v, s) pairs.
    a = parent[v]
    while a >= 0:
        for s in range(n):
            if in_s[s]:
                _add_pair(viol, truth_t, base + a * n + s, -1)
                n_conj -= 1
        a = parent[a]
    parent[v] = -1
    # cost[a, d]: violations added by making a an ancestor of the whole subtree.
    for a in range(n):
        if in_s[a]:
            continue
        for d in range(D):
            cost[a, d] = 0
        for s in range(n):
            if in_s[s]:
                c = base + a * n + s
                for d in range(D):
                    cost[a, d] += 1 if truth_t[c, d] == 0 else 0
    # Subtree sizes with S cut off (S's own sizes do not change when it is regrafted), and
    # the log prior of that forest: regrafting S under u adds size_s to u and its ancestors.
    for u in range(n):
        size[u] = 1
    for u in range(n):
        a = parent[u]
        while a >= 0:
            size[a] += 1
            a = parent[a]
    lp_cut = g_const
    for u in range(n):
        lp_cut += g[size[u]]
    k = 0
    for u in range(-1, n):
        if u >= 0 and in_s[u]:
            continue
        for d in range(D):
            cur[d] = viol[d]
        depth = 0
        lp = lp_cut
        a = u
        while a >= 0:
            for d in range(D):
                cur[d] += cost[a, d]
            lp += g[size[a] + size_s] - g[size[a]]
            depth += 1
            a = parent[a]
        ps, ns = _sat_counts(cur, w_pos, w_neg)
        cand_lp[k] = lp
        lw[k] = lp + log_likelihood(ps, ns, n_pos, n_neg, n_conj + depth * size_s,
                                    log_eps, lik_code)
        cand_head[k] = u
        k += 1
    j = _draw(lw, k, unif, cand_ew)
    u = cand_head[j]
    parent[v] = u
    a = u
    while a >= 0:
        for d in range(D):
            viol[d] += cost[a, d]
        n_conj += size_s
        a = parent[a]
    return n_conj, cand_lp[j], lw[j] - cand_lp[j]


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
            _add_pair(viol, truth_t, j, 1)
            n_conj += 1
    for w in range(n):
        if w1[w]:
            _add_pair(viol, truth_t, n_g + w, 1)
            n_conj += 1
    for v in range(n):
        a = parent[v]
        while a >= 0:
            _add_pair(viol, truth_t, n_g + n + a * n + v, 1)
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
    ps, ns = _sat_counts(viol, demos.w_pos, demos.w_neg)
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
            new, ll, used = _flip_move(j, tau[j], lg_in, lg_out, viol, n_conj, demos, model,
                                       ubuf[upos])
            upos += used
            if new != tau[j]:
                n_conj += 1 if new else -1
                lp_sub += (lg_in - lg_out) if new else (lg_out - lg_in)
                tau[j] = new
                moved += 1
        for w in range(n):
            new, ll, used = _flip_move(n_g + w, w1[w], le_in, le_out, viol, n_conj, demos,
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
                    n_conj, lp_struct, ll = _forest_move(v, parent, viol, n_conj, demos, model,
                                                         bufs, ubuf[upos])
                else:
                    n_conj, lp_struct, ll = _chain_move(v, parent, viol, n_conj, demos, model,
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
        Deduplicated clause truth and label weights (:func:`make_demos`).
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
        ps, ns = _sat_counts(viol, demos.w_pos, demos.w_neg)
        out[r] = log_prior(tau, w1, parent, model) + log_likelihood(
            ps, ns, demos.n_pos, demos.n_neg, n_conj, model.log_eps, model.likelihood)
    return out
