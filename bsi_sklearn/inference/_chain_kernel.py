"""The numba kernel of one MCMC chain: Gibbs sweeps of tempered replicas and swaps between them.

A chain holds ``R`` replicas of the hypothesis (τ, W1, order structure), one per rung of a
ladder of inverse temperatures ``1 = beta_0 > beta_1 > ... > beta_{R-1}``; the replica on rung
``k`` targets ``prior x likelihood^beta_k``. A sweep updates every coordinate of every replica
once (Gibbs flips of the τ bits; Gibbs re-insertion of every subtask with its eventual bit,
:mod:`bsi_sklearn.inference._gibbs_moves`), then proposes swaps between adjacent rungs (even
pairs after even sweeps, odd pairs after odd ones), each accepted with probability
``min(1, exp((beta_k - beta_{k+1}) (ll_{k+1} - ll_k)))``: the prior cancels, and every move
leaves the product of the tempered targets invariant. Only the replica on rung 0 (beta = 1) is
recorded. With one rung this is the plain Gibbs sampler.

The kernel keeps, per (deduplicated) demonstration and replica, the number of clauses of the
hypothesis it violates; a demonstration satisfies the hypothesis when that count is zero.
Traces are never read: only the precomputed clause-truth matrix is.
"""

import math
from typing import NamedTuple

import numpy as np
from numba import carray, njit
from numba.core import types
from numba.extending import intrinsic

from bsi_sklearn._jit import helper
from bsi_sklearn.inference._gibbs_moves import (
    add_pair,
    chain_move,
    draw,
    flip_move,
    forest_move,
)
from bsi_sklearn.inference._row_counts import flip_masks, sat_counts
from bsi_sklearn.model import Model
from bsi_sklearn.model.clauses import clause_index_eventual, clause_index_order
from bsi_sklearn.model.likelihood import cb_rejected, log_likelihood
from bsi_sklearn.model.priors import (
    global_inclusion,
    is_forest,
    log_prior,
    log_prior_globals,
    log_prior_structure,
    log_prior_subset,
    n_plain_globals,
    subset_inclusion,
)
from bsi_sklearn.model.state_layout import max_conjuncts, split_state, state_width

__all__ = ["Demos", "ChainState", "ChainBuffers", "ChainLoop", "make_buffers", "make_loop",
           "chain_kernel", "add_structure_viol",
           "init_viol", "fill_viol", "score_one", "score_rows", "violation_rows"]


class Demos(NamedTuple):
    """Deduplicated clause truth, clause-major, with the labels as weights.

    Also packed, for the structure moves' bitsets: row ``d`` is bit ``d & 63`` of word
    ``d >> 6``; the weights as bit-planes (plane ``k`` holds bit ``k`` of every row's weight),
    so that a weighted count is a sum of popcounts. Built by ``mcmc.deduplicate_demos``.
    """

    truth_t: np.ndarray     # (n_clauses, n_unique) uint8
    w_pos: np.ndarray       # (n_unique,) float64: acceptable demonstrations behind each row
    w_neg: np.ndarray       # (n_unique,) float64: unacceptable ones
    n_pos: float            # w_pos.sum()
    n_neg: float            # w_neg.sum()
    bits: np.ndarray        # (n_clauses, n_words) uint64: truth_t packed
    pos_planes: np.ndarray  # (n_planes, n_words) uint64: w_pos by bit-plane
    neg_planes: np.ndarray  # (n_planes, n_words) uint64: w_neg by bit-plane


class ChainState(NamedTuple):
    """The replicas of a chain: inclusion bits of tau and W1, parent arrays (one row each)."""

    tau: np.ndarray       # (R, n_g) int64
    w1: np.ndarray        # (R, n) int64
    parent: np.ndarray    # (R, n) int64


class ChainBuffers(NamedTuple):
    """Scratch space of one chain, allocated once by :func:`make_buffers`."""

    ubuf: np.ndarray      # uniforms, refilled in bulk
    viol: np.ndarray      # (R, D) int32: clauses of each replica's hypothesis each row violates
    lw: np.ndarray        # candidate log weights (prior + beta x likelihood)
    cand_lp: np.ndarray   # candidate log priors of the structure
    cand_ll: np.ndarray   # candidate log-likelihoods
    cand_head: np.ndarray
    cand_pos: np.ndarray
    cand_ew: np.ndarray   # exponentiated weights
    child: np.ndarray     # (n,) chain successor (Priors 1, 2)
    in_s: np.ndarray      # (n,) membership of the pruned subtree (Prior 3)
    size: np.ndarray      # (n,) subtree sizes (Prior 3)
    old_parent: np.ndarray
    zmask: np.ndarray     # (1, W) uint64: the rows a structure move weighs its candidates over
    fmask: np.ndarray     # (2, W) uint64: the rows violating no clause / one (flip_masks)
    suf: np.ndarray       # (n + 1, W) uint64: zmask AND a chain's suffix of (v -> u) clauses
    acc: np.ndarray       # (1, W) uint64: a running AND
    ones: np.ndarray      # (1, W) uint64: every bit set
    anc: np.ndarray       # (n, W) uint64: rows an ancestor keeps satisfied (Prior 3)
    members: np.ndarray   # (n,) int64: one chain's subtasks in order
    lw_cache: np.ndarray  # (R, n, K) the last weights of each replica's moves (see _sweep)
    cache_k: np.ndarray   # (R, n) int64: their number of candidates
    cache_j: np.ndarray   # (R, n) int64: the candidate drawn (the subtask's place since)
    cache_ver: np.ndarray  # (R, n) int64: the replica's version they were computed at
    cache_beta: np.ndarray  # (R, n) float64: and its inverse temperature
    version: np.ndarray   # (R,) int64: changes of each replica's state (moves and flips)
    cb_rejected: np.ndarray  # (max N + 2,) likelihood.cb_rejected(N), by number of conjuncts


def make_buffers(n_g, n, n_rows, n_rungs):
    """Scratch buffers of a chain with ``n_rungs`` replicas over ``n_rows`` unique rows."""
    k = 2 * (2 * n + 2)  # the most candidates of one structure move (places x eventual bit)
    need = state_width(n_g, n) + n_rungs  # one uniform per entry of a state, the swaps
    n_words = (n_rows + 63) // 64
    return ChainBuffers(
        ubuf=np.empty(max(1024, 2 * need)),
        viol=np.zeros((n_rungs, n_rows), dtype=np.int32),
        lw=np.empty(k), cand_lp=np.empty(k), cand_ll=np.empty(k),
        cand_head=np.empty(k, dtype=np.int64), cand_pos=np.empty(k, dtype=np.int64),
        cand_ew=np.empty(k),
        child=np.empty(n, dtype=np.int64), in_s=np.zeros(n, dtype=np.int64),
        size=np.empty(n, dtype=np.int64), old_parent=np.empty(n, dtype=np.int64),
        zmask=np.zeros((1, n_words), dtype=np.uint64),
        fmask=np.zeros((2, n_words), dtype=np.uint64),
        suf=np.zeros((n + 1, n_words), dtype=np.uint64),
        acc=np.zeros((1, n_words), dtype=np.uint64),
        ones=np.full((1, n_words), np.iinfo(np.uint64).max, dtype=np.uint64),
        anc=np.zeros((max(n, 1), n_words), dtype=np.uint64),
        members=np.empty(max(n, 1), dtype=np.int64),
        lw_cache=np.empty((n_rungs, max(n, 1), k)),
        cache_k=np.zeros((n_rungs, max(n, 1)), dtype=np.int64),
        cache_j=np.zeros((n_rungs, max(n, 1)), dtype=np.int64),
        cache_ver=np.full((n_rungs, max(n, 1)), -1, dtype=np.int64),
        cache_beta=np.zeros((n_rungs, max(n, 1))),
        version=np.zeros(n_rungs, dtype=np.int64),
        cb_rejected=np.array([cb_rejected(k) for k in range(max_conjuncts(n_g, n) + 2)]),
    )


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
                  demos.n_pos, demos.n_neg, _unmanaged(demos.bits),
                  _unmanaged(demos.pos_planes), _unmanaged(demos.neg_planes))
    model = Model(model.n_g, model.n, model.prior, model.forest, model.p_global,
                  model.p_eventual, model.p_part, model.n_new, model.log_eps, model.likelihood,
                  _unmanaged(model.lp_chains), _unmanaged(model.forest_g), model.forest_const,
                  model.flip_a, model.flip_b, _unmanaged(model.pat_in), _unmanaged(model.pat_out),
                  _unmanaged(model.flips))
    bufs = ChainBuffers(_unmanaged(bufs.ubuf), _unmanaged(bufs.viol),
                        _unmanaged(bufs.lw), _unmanaged(bufs.cand_lp), _unmanaged(bufs.cand_ll),
                        _unmanaged(bufs.cand_head), _unmanaged(bufs.cand_pos),
                        _unmanaged(bufs.cand_ew), _unmanaged(bufs.child), _unmanaged(bufs.in_s),
                        _unmanaged(bufs.size), _unmanaged(bufs.old_parent),
                        _unmanaged(bufs.zmask), _unmanaged(bufs.fmask), _unmanaged(bufs.suf),
                        _unmanaged(bufs.acc),
                        _unmanaged(bufs.ones), _unmanaged(bufs.anc), _unmanaged(bufs.members),
                        _unmanaged(bufs.lw_cache), _unmanaged(bufs.cache_k),
                        _unmanaged(bufs.cache_j), _unmanaged(bufs.cache_ver),
                        _unmanaged(bufs.cache_beta), _unmanaged(bufs.version),
                        _unmanaged(bufs.cb_rejected))
    return state, demos, model, bufs


@njit(cache=True, nogil=True)
def init_viol(tau, w1, parent, truth_t, model):
    """Per-row violation counts of a hypothesis (int32) and its number of conjuncts."""
    # int32 counts (not int64): twice as many lanes in the kernels' vectorised loops.
    viol = np.zeros(truth_t.shape[1], dtype=np.int32)
    return viol, fill_viol(viol, tau, w1, parent, truth_t, model)


@njit(cache=True, nogil=True)
def fill_viol(viol, tau, w1, parent, truth_t, model):
    """Per demonstration, the number of the hypothesis' clauses it violates, into ``viol``.

    Returns the hypothesis' number of conjuncts.
    """
    viol[:] = 0
    n_conj = 0
    for j in range(model.n_g):
        if tau[j]:
            add_pair(viol, truth_t, j, np.int64(1))
            n_conj += 1
    return n_conj + add_structure_viol(viol, w1, parent, truth_t, model)


@helper
def add_structure_viol(viol, w1, parent, truth_t, model):
    """Add the violations of the eventual and order clauses to ``viol``; their number."""
    n_g, n = model.n_g, model.n
    n_conj = 0
    for w in range(n):
        if w1[w]:
            add_pair(viol, truth_t, clause_index_eventual(w, n_g), np.int64(1))
            n_conj += 1
    for v in range(n):
        a = parent[v]
        while a >= 0:
            add_pair(viol, truth_t, clause_index_order(a, v, n_g, n), np.int64(1))
            n_conj += 1
            a = parent[a]
    return n_conj


@njit(cache=True, nogil=True)
def score_one(tau, w1, parent, demos, model):
    """Exact unnormalised ``(log prior, log-likelihood)`` of one hypothesis."""
    viol, n_conj = init_viol(tau, w1, parent, demos.truth_t, model)
    ps, ns = sat_counts(viol, demos.w_pos, demos.w_neg)
    return log_prior(tau, w1, parent, model), log_likelihood(
        ps, ns, demos.n_pos, demos.n_neg, n_conj, model.log_eps, model.likelihood, model.flips)


@njit(cache=True, nogil=True)
def score_rows(states, demos, model):
    """Exact unnormalised log posterior of every state row ``[tau, w1, parent]``."""
    out = np.empty(states.shape[0])
    for r in range(states.shape[0]):
        tau, w1, parent = split_state(states[r], model.n_g, model.n)
        lp, ll = score_one(tau.astype(np.int64), w1.astype(np.int64), parent.astype(np.int64),
                           demos, model)
        out[r] = lp + ll
    return out


@njit(cache=True, nogil=True)
def violation_rows(states, demos, model):
    """Misclassified demonstrations of every state row ``[tau, w1, parent]``.

    The acceptable ones it violates plus the unacceptable ones it satisfies (weighted).
    """
    out = np.empty(states.shape[0])
    for r in range(states.shape[0]):
        tau, w1, parent = split_state(states[r], model.n_g, model.n)
        viol, _ = init_viol(tau.astype(np.int64), w1.astype(np.int64), parent.astype(np.int64),
                            demos.truth_t, model)
        ps, ns = sat_counts(viol, demos.w_pos, demos.w_neg)
        out[r] = demos.n_pos - ps + ns
    return out


@njit(cache=True, nogil=True)
def _sweep(r, beta, state, demos, model, bufs, cache, u0):
    # One Gibbs sweep of replica r at inverse temperature beta, from uniforms ubuf[u0:]:
    # every tau bit, then every subtask's place with its eventual bit (the W1 bits alone
    # when there is no order to redraw). cache = (n_conj, lp_sub, lp_struct, ll) per replica.
    # Returns (uniforms used, coordinates that changed).
    n_conj, lp_sub, lp_struct, ll = cache
    tau, w1, parent, viol = state.tau[r], state.w1[r], state.parent[r], bufs.viol[r]
    ubuf, old_parent = bufs.ubuf, bufs.old_parent
    n_g, n = model.n_g, model.n
    n_gp = n_g - model.pat_in.shape[0]
    # Included G slots and W1 bits: a learned inclusion probability weighs one more by them.
    k_g = n_plain_globals(tau, model)
    k_w = 0
    for w in range(n):
        k_w += w1[w]
    upos = u0
    moved = 0
    fmask = bufs.fmask
    flip_masks(viol, fmask)
    for j in range(n_g):
        plain = j < n_gp
        lg_in, lg_out = global_inclusion(j, model, k_g - tau[j] if plain else 0)
        new, ll[r], used = flip_move(j, tau[j], lg_in, lg_out, viol, fmask, n_conj[r], demos,
                                     model, ubuf[upos], beta)
        upos += used
        if new != tau[j]:
            n_conj[r] += 1 if new else -1
            lp_sub[r] += (lg_in - lg_out) if new else (lg_out - lg_in)
            if plain:
                k_g += 1 if new else -1
            tau[j] = new
            moved += 1
            bufs.version[r] += 1
    if n <= 1:
        for w in range(n):
            le_in, le_out = subset_inclusion(k_w - w1[w], n, model.p_eventual)
            new, ll[r], used = flip_move(clause_index_eventual(w, n_g), w1[w], le_in, le_out,
                                         viol, fmask, n_conj[r], demos, model, ubuf[upos],
                                         beta)
            upos += used
            if new != w1[w]:
                n_conj[r] += 1 if new else -1
                lp_sub[r] += (le_in - le_out) if new else (le_out - le_in)
                k_w += 1 if new else -1
                w1[w] = new
                moved += 1
        return upos - u0, moved
    lw_cache, cache_k, cache_j = bufs.lw_cache, bufs.cache_k, bufs.cache_j
    cache_ver, cache_beta, version = bufs.cache_ver, bufs.cache_beta, bufs.version
    for v in range(n):
        # A move's candidates depend on the rest of the replica's state and on beta only: when
        # neither changed since v's last move, its weights are the ones kept then, and a draw
        # that lands on v's present place (the one drawn then) moves nothing. Any other draw
        # redoes the move, which computes the same weights and draws the same candidate.
        if cache_ver[r, v] == version[r] and cache_beta[r, v] == beta:
            if draw(lw_cache[r, v], cache_k[r, v], ubuf[upos],
                    bufs.cand_ew) == cache_j[r, v]:
                upos += 1
                continue
        for u in range(n):  # element loops, not slice copies: cheaper to compile
            old_parent[u] = parent[u]
        old_w = w1[v]
        if is_forest(model):
            n_conj[r], lp_struct[r], ll[r], n_cand, j = forest_move(
                v, parent, w1, viol, n_conj[r], demos, model, bufs, ubuf[upos], beta)
        else:
            n_conj[r], lp_struct[r], ll[r], n_cand, j = chain_move(
                v, parent, w1, viol, n_conj[r], demos, model, bufs, ubuf[upos], beta)
        upos += 1  # a structure move always draws
        changed = w1[v] != old_w
        if changed:
            le_in, le_out = subset_inclusion(k_w - old_w, n, model.p_eventual)
            lp_sub[r] += (le_in - le_out) if w1[v] else (le_out - le_in)
            k_w += 1 if w1[v] else -1
        for u in range(n):
            if parent[u] != old_parent[u]:
                changed = True
                break
        if changed:
            moved += 1
            version[r] += 1
        for i in range(n_cand):
            lw_cache[r, v, i] = bufs.lw[i]
        cache_k[r, v] = n_cand
        cache_j[r, v] = j
        cache_ver[r, v] = version[r]
        cache_beta[r, v] = beta
    return upos - u0, moved


@njit(cache=True, nogil=True)
def _same_state(state, i, j):
    # Whether replicas i and j hold the same hypothesis.
    for a in range(state.tau.shape[1]):
        if state.tau[i, a] != state.tau[j, a]:
            return False
    for a in range(state.w1.shape[1]):
        if state.w1[i, a] != state.w1[j, a] or state.parent[i, a] != state.parent[j, a]:
            return False
    return True


@njit(cache=True, nogil=True)
def _record(states, k, state, r, n_g, n):
    # Write replica r's state into row k + 1 unless it equals row k; returns the new k and
    # whether a row was written.
    if k >= 0:
        tau, w1, parent = split_state(states[k], n_g, n)
        same = True
        for j in range(n_g):
            if tau[j] != state.tau[r, j]:
                same = False
        for w in range(n):
            if w1[w] != state.w1[r, w] or parent[w] != state.parent[r, w]:
                same = False
        if same:
            return k, False
    k += 1
    tau, w1, parent = split_state(states[k], n_g, n)
    for j in range(n_g):
        tau[j] = state.tau[r, j]
    for w in range(n):
        w1[w] = state.w1[r, w]
        parent[w] = state.parent[r, w]
    return k, True


class ChainLoop(NamedTuple):
    """Where a chain stands between calls of :func:`chain_kernel` (see :func:`make_loop`).

    A chain run in several calls carries these, its state and its buffers (the uniforms not
    yet used among them) from one call to the next: the calls then draw exactly the numbers
    one long call would, and record the same states.
    """

    slot: np.ndarray       # (R,) int64: slot[k] is the replica on rung k
    swaps: np.ndarray      # (R - 1,) int64: accepted swaps between rungs k and k + 1
    accept: np.ndarray     # (R - 1,): their acceptance probabilities, summed over the tries
    counters: np.ndarray   # int64: sweeps, burned (-1: burning), upos, moved, updates, started
    n_conj: np.ndarray     # (R,) int64: every replica's number of conjuncts
    lp_sub: np.ndarray     # (R,): log prior of its subsets
    lp_struct: np.ndarray  # (R,): log prior of its structure
    ll: np.ndarray         # (R,): log-likelihood


def make_loop(n_rungs):
    """A chain's :class:`ChainLoop` before its first sweep."""
    return ChainLoop(np.arange(n_rungs), np.zeros(max(n_rungs - 1, 0), dtype=np.int64),
                     np.zeros(max(n_rungs - 1, 0)),
                     np.array([0, -1, 0, 0, 0, 0], dtype=np.int64),
                     np.zeros(n_rungs, dtype=np.int64), np.zeros(n_rungs),
                     np.zeros(n_rungs), np.zeros(n_rungs))


@njit(cache=True, nogil=True)
def _init_cache(state, demos, model, bufs, loop):
    # Violation counts of every replica into bufs.viol, and per replica the number of
    # conjuncts, log priors (subsets, structure) and log-likelihood the moves keep up to date.
    n = model.n
    for r in range(loop.slot.shape[0]):
        viol = bufs.viol[r]
        loop.n_conj[r] = fill_viol(viol, state.tau[r], state.w1[r], state.parent[r],
                                   demos.truth_t, model)
        loop.lp_sub[r] = (log_prior_globals(state.tau[r], model)
                          + log_prior_subset(state.w1[r].sum(), n, model.p_eventual))
        loop.lp_struct[r] = log_prior_structure(state.parent[r], model)
        ps, ns = sat_counts(viol, demos.w_pos, demos.w_neg)
        loop.ll[r] = log_likelihood(ps, ns, demos.n_pos, demos.n_neg, loop.n_conj[r],
                                    model.log_eps, model.likelihood, model.flips)


@njit(cache=True, nogil=True)
def chain_kernel(state, demos, model, bufs, betas, rng, loop, n_samples, burn_in, target,
                 max_extra):
    """Run one tempered chain; record the beta = 1 replica after every sweep past burn-in.

    ``state`` holds the replicas' hypotheses (row ``k`` starts on rung ``k``) and is updated
    in place, as are ``bufs`` and ``loop`` (:class:`ChainLoop`): a call resumes where the last
    one stopped. Burn-in lasts ``burn_in`` sweeps, and then on while the beta = 1 replica's
    log posterior is below ``target``, for at most ``max_extra`` more sweeps; this call
    records ``n_samples`` sweeps after it. ``betas`` is the ladder, ``betas[0] = 1``. Returns
    ``(states, counts, trace_lp)``: this call's recorded rows run-length encoded and the log
    posterior after every recorded sweep; the swaps, sweeps, moves and burn-in are in
    ``loop``.
    """
    # The state and the scratch buffers (allocated by the caller) are used through unmanaged
    # views: see _unmanaged.
    state, demos, model, bufs = _unmanaged_bundles(state, demos, model, bufs)
    n_g, n = model.n_g, model.n
    n_rungs = betas.shape[0]
    # Uniforms come from a buffer refilled in bulk (the same stream as one rng.random() per
    # draw), so that the generator, a managed object, is not passed to every move.
    ubuf = bufs.ubuf
    n_u = ubuf.shape[0]
    counters, slot, swaps = loop.counters, loop.slot, loop.swaps
    if counters[5] == 0:
        _init_cache(state, demos, model, bufs, loop)
        counters[2] = n_u  # the buffer is empty
        counters[5] = 1
    sweep, burned, upos, moved, updates = (counters[0], counters[1], counters[2],
                                           counters[3], counters[4])
    # The most uniforms of one replica's sweep (one per entry of its state) and the swaps.
    need = state_width(n_g, n) + n_rungs
    cache = (loop.n_conj, loop.lp_sub, loop.lp_struct, loop.ll)
    ll = loop.ll
    states = np.empty((n_samples, state_width(n_g, n)), dtype=np.int16)
    trace_lp = np.empty(n_samples)
    counts = np.zeros(n_samples, dtype=np.int64)
    per_sweep = n_g + n  # blocks one sweep updates
    k = -1
    row = 0
    while row < n_samples:
        for t in range(n_rungs):
            if upos + need > n_u:
                rest = n_u - upos
                for i in range(rest):
                    ubuf[i] = ubuf[upos + i]
                fresh = rng.random(n_u - rest)
                for i in range(n_u - rest):
                    ubuf[rest + i] = fresh[i]
                upos = 0
            used, m = _sweep(slot[t], betas[t], state, demos, model, bufs, cache, upos)
            upos += used
            if t == 0:
                moved += m
                updates += per_sweep
        # Swaps between adjacent rungs, even and odd pairs in turn.
        for t in range(sweep & 1, n_rungs - 1, 2):
            i, j = slot[t], slot[t + 1]
            log_a = (betas[t] - betas[t + 1]) * (ll[j] - ll[i])
            # Its probability is summed too, for the ladder's pilot (_ladder.pilot_rejection);
            # a uniform is below 1, so the draw is the same as accepting when log_a >= 0.
            p_a = 1.0 if log_a >= 0.0 else math.exp(log_a)
            loop.accept[t] += p_a
            if ubuf[upos] < p_a:
                # Replicas in the same state (the cold rungs of a peaked posterior) keep
                # their rungs: exchanging them changes nothing but would make their kept
                # move weights (_sweep) useless.
                if not _same_state(state, i, j):
                    slot[t], slot[t + 1] = j, i
                swaps[t] += 1
            upos += 1
        r = slot[0]
        lp0 = loop.lp_sub[r] + loop.lp_struct[r] + ll[r]
        sweep += 1
        if burned < 0:
            if sweep <= burn_in or (lp0 < target and sweep <= burn_in + max_extra):
                continue
            burned = sweep - 1
        trace_lp[row] = lp0
        k, _ = _record(states, k, state, r, n_g, n)
        counts[k] += 1
        row += 1
    counters[0], counters[1], counters[2], counters[3], counters[4] = (sweep, burned, upos,
                                                                       moved, updates)
    return states[:k + 1], counts[:k + 1], trace_lp
