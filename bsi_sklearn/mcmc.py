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

import numpy as np
from numba import carray, njit
from numba.core import types
from numba.extending import intrinsic

from bsi_sklearn.likelihood import log_likelihood
from bsi_sklearn.priors import log_prior_structure, log_prior_subset, sample_hypothesis

__all__ = ["run_chain", "deduplicate_demos", "split_rhat", "score_states", "unique_states"]


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
def _flip_move(c, inc, lp_in, lp_out, viol, truth_t, w_pos, w_neg, n_pos, n_neg, n_conj,
               log_eps, lik_code, u):
    # Gibbs update of one inclusion bit: returns the new bit, the new log-likelihood and
    # whether the uniform u was used (only when both outcomes are possible).
    ps_out, ns_out, ps_in, ns_in = _flip_sums(viol, truth_t, c, inc, w_pos, w_neg)
    n_out = n_conj - inc
    ll_out = log_likelihood(ps_out, ns_out, n_pos, n_neg, n_out, log_eps, lik_code)
    ll_in = log_likelihood(ps_in, ns_in, n_pos, n_neg, n_out + 1, log_eps, lik_code)
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
def _chain_move(v, parent, viol, truth_t, w_pos, w_neg, n_pos, n_neg, n_conj, base,
                n, code, p_part, n_new, log_eps, lik_code, unif, cur, lw, cand_lp, cand_head,
                cand_pos, child, cand_ew, lp_chains):
    # Prior 1 / 2: take v out of its chain and redraw its place.
    # Returns (n_conj, log prior of the structure, log-likelihood) of the new state.
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
    # Candidates: every position of every remaining chain, plus a new chain (Prior 2).
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
    if code == 1 or k == 0:
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
def log_prior_structure_chains(n, m, code, p_part):
    """Log prior of a chain structure with ``m`` chains over ``n`` subtasks (Priors 1, 2)."""
    if code == 0:
        if m != 1:
            return -np.inf
        return -math.lgamma(n + 1.0)
    lp = math.lgamma(m + 1.0) - math.lgamma(n + 1.0)
    if m - 1 > 0:
        lp += (m - 1) * math.log(p_part) if p_part > 0 else -np.inf
    if n - m > 0:
        lp += (n - m) * math.log(1.0 - p_part) if p_part < 1 else -np.inf
    return lp


@njit(cache=True, nogil=True)
def _forest_size_terms(n, n_new):
    """Prior 3 (``priors.log_prior_structure``, code 2) as a sum over subtree sizes.

    Every subtask v with subtree size s_v enters the forest prior through lgamma(s_v) (its
    block in its parent's, or the top-level, CRP partition), -log(s_v) (its root is its
    first element) and, when s_v > 1, the CRP normaliser lgamma(theta) - lgamma(theta + s_v
    - 1) of its descendants' partition. The per-block log(theta) terms add up to
    n log(theta) (every subtask is a root or one parent's child). So
    ``log p = const + sum_v g[s_v]``; returns ``(g, const)``.
    """
    log_theta = math.log(n_new)
    lg0 = math.lgamma(n_new)
    g = np.zeros(n + 2)
    for k in range(1, n + 1):
        g[k] = math.lgamma(float(k)) - math.log(float(k))
        if k > 1:
            g[k] += lg0 - math.lgamma(n_new + k - 1)
    return g, n * log_theta + lg0 - math.lgamma(n_new + n)


@njit(cache=True, nogil=True)
def _forest_move(v, parent, viol, truth_t, w_pos, w_neg, n_pos, n_neg, n_conj, base,
                 n, p_part, n_new, log_eps, lik_code, unif, cur, lw, cand_lp, cand_head, in_s,
                 cost, g, g_const, size, cand_ew):
    # Prior 3: prune the subtree rooted at v and regraft it anywhere outside it.
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
def _log_prior_total(tau, w1, parent, code, p_global, p_eventual, p_part, n_new):
    return (log_prior_subset(tau.sum(), tau.shape[0], p_global)
            + log_prior_subset(w1.sum(), w1.shape[0], p_eventual)
            + log_prior_structure(parent, code, p_part, n_new))


@njit(cache=True, nogil=True)
def _init_viol(tau, w1, parent, truth_t, n_g, n):
    # int32 counts (not int64): twice as many lanes in the kernels' vectorised loops.
    viol = np.zeros(truth_t.shape[1], dtype=np.int32)
    return viol, _fill_viol(viol, tau, w1, parent, truth_t, n_g, n)


@njit(cache=True, nogil=True)
def _fill_viol(viol, tau, w1, parent, truth_t, n_g, n):
    # Per demonstration, the number of clauses of the hypothesis it violates; returns N.
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
def _chain_kernel(tau, w1, parent, truth_t, w_pos, w_neg, n_g, n, code, p_global,
                  p_eventual, p_part, n_new, log_eps, lik_code, n_sweeps, burn_in, rng, ubuf,
                  viol, cur, lw, cand_lp, cand_head, cand_pos, cand_ew, child, in_s, cost, g,
                  g_const, lp_chains, size, old_parent):
    # One sweep updates every coordinate once (tau bits, W1 bits, every subtask's place);
    # the state is recorded after each sweep past burn-in. The state and the scratch buffers
    # (allocated by run_chain) are used through unmanaged views: see _unmanaged.
    tau = _unmanaged(tau)
    w1 = _unmanaged(w1)
    parent = _unmanaged(parent)
    truth_t = _unmanaged(truth_t)
    w_pos = _unmanaged(w_pos)
    w_neg = _unmanaged(w_neg)
    viol = _unmanaged(viol)
    cur = _unmanaged(cur)
    lw = _unmanaged(lw)
    cand_lp = _unmanaged(cand_lp)
    cand_head = _unmanaged(cand_head)
    cand_pos = _unmanaged(cand_pos)
    cand_ew = _unmanaged(cand_ew)
    child = _unmanaged(child)
    in_s = _unmanaged(in_s)
    cost = _unmanaged(cost)
    g = _unmanaged(g)
    lp_chains = _unmanaged(lp_chains)
    size = _unmanaged(size)
    old_parent = _unmanaged(old_parent)
    # Uniforms come from a buffer refilled in bulk (the same stream as one rng.random() per
    # draw), so that the generator, a managed object, is not passed to every move.
    ubuf = _unmanaged(ubuf)
    n_u = ubuf.shape[0]
    upos = n_u
    n_pos = w_pos.sum()
    n_neg = w_neg.sum()
    n_conj = _fill_viol(viol, tau, w1, parent, truth_t, n_g, n)
    base = n_g + n
    n_keep = n_sweeps - burn_in
    states = np.empty((n_keep, n_g + 2 * n), dtype=np.int16)
    trace_lp = np.empty(n_keep)
    lg_in = math.log(p_global) if p_global > 0 else -np.inf
    lg_out = math.log1p(-p_global) if p_global < 1 else -np.inf
    le_in = math.log(p_eventual) if p_eventual > 0 else -np.inf
    le_out = math.log1p(-p_eventual) if p_eventual < 1 else -np.inf
    lp_sub = (log_prior_subset(tau.sum(), n_g, p_global)
              + log_prior_subset(w1.sum(), n, p_eventual))
    lp_struct = log_prior_structure(parent, code, p_part, n_new)
    ps, ns = _sat_counts(viol, w_pos, w_neg)
    ll = log_likelihood(ps, ns, n_pos, n_neg, n_conj, log_eps, lik_code)
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
            new, ll, used = _flip_move(j, tau[j], lg_in, lg_out, viol, truth_t, w_pos, w_neg,
                                       n_pos, n_neg, n_conj, log_eps, lik_code, ubuf[upos])
            upos += used
            if new != tau[j]:
                n_conj += 1 if new else -1
                lp_sub += (lg_in - lg_out) if new else (lg_out - lg_in)
                tau[j] = new
                moved += 1
        for w in range(n):
            new, ll, used = _flip_move(n_g + w, w1[w], le_in, le_out, viol, truth_t, w_pos,
                                       w_neg, n_pos, n_neg, n_conj, log_eps, lik_code,
                                       ubuf[upos])
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
                if code == 2:
                    n_conj, lp_struct, ll = _forest_move(
                        v, parent, viol, truth_t, w_pos, w_neg, n_pos, n_neg, n_conj, base, n,
                        p_part, n_new, log_eps, lik_code, ubuf[upos], cur, lw, cand_lp,
                        cand_head, in_s, cost, g, g_const, size, cand_ew)
                else:
                    n_conj, lp_struct, ll = _chain_move(
                        v, parent, viol, truth_t, w_pos, w_neg, n_pos, n_neg, n_conj, base, n,
                        code, p_part, n_new, log_eps, lik_code, ubuf[upos], cur, lw, cand_lp,
                        cand_head, cand_pos, child, cand_ew, lp_chains)
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


def run_chain(seed, truth_t, w_pos, w_neg, n_g, n, prior_code, prior_name, p_global,
              p_eventual, p_part, n_new, log_eps, lik_code, n_samples, burn_in):
    """Run one chain from a prior draw.

    A sample is one Gibbs sweep (every coordinate updated once). Returns the recorded states,
    run-length encoded (rows ``[tau (n_g), w1 (n), parent (n)]`` of int16 and how many
    consecutive samples each row stands for), the log posterior after every sweep, the fraction
    of coordinate updates that changed the state, and the number of updates.
    """
    rng = np.random.default_rng(seed)
    tau, w1, parent = sample_hypothesis(prior_name, n_g, n, rng, p_global, p_eventual,
                                        p_part, n_new)
    # The kernel's state and scratch buffers live here, for the whole call (see _unmanaged).
    tau = np.ascontiguousarray(tau, dtype=np.int64)
    w1 = np.ascontiguousarray(w1, dtype=np.int64)
    parent = np.ascontiguousarray(parent, dtype=np.int64)
    truth_t = np.ascontiguousarray(truth_t)
    w_pos = np.ascontiguousarray(w_pos, dtype=np.float64)
    w_neg = np.ascontiguousarray(w_neg, dtype=np.float64)
    D = truth_t.shape[1]
    k = 2 * n + 2  # the most candidate places of one structure move
    g, g_const = _forest_size_terms(n, n_new)
    # Log prior of a chain structure by its number of chains (Priors 1, 2), looked up per move.
    lp_chains = np.array([log_prior_structure_chains(n, m, prior_code, p_part)
                          for m in range(n + 2)], dtype=np.float64)
    uniforms = np.empty(max(1024, 2 * (n_g + 2 * n)))
    viol, cur = np.zeros(D, dtype=np.int32), np.empty(D, dtype=np.int32)
    lw, cand_lp, cand_ew = np.empty(k), np.empty(k), np.empty(k)
    cand_head, cand_pos = np.empty(k, dtype=np.int64), np.empty(k, dtype=np.int64)
    child, in_s = np.empty(n, dtype=np.int64), np.zeros(n, dtype=np.int64)
    size, old_parent = np.empty(n, dtype=np.int64), np.empty(n, dtype=np.int64)
    cost = np.zeros((n, D), dtype=np.int32)
    return _chain_kernel(
        tau, w1, parent, truth_t, w_pos, w_neg, n_g, n, prior_code, p_global, p_eventual,
        p_part, n_new, log_eps, lik_code, burn_in + n_samples, burn_in, rng, uniforms, viol,
        cur, lw, cand_lp, cand_head, cand_pos, cand_ew, child, in_s, cost, g, g_const,
        lp_chains, size, old_parent)


@njit(cache=True, nogil=True)
def score_states(states, truth_t, w_pos, w_neg, n_g, n, code, p_global, p_eventual, p_part,
                 n_new, log_eps, lik_code):
    """Exact unnormalised log posterior of every state row."""
    n_pos = w_pos.sum()
    n_neg = w_neg.sum()
    out = np.empty(states.shape[0])
    for r in range(states.shape[0]):
        tau = states[r, :n_g].astype(np.int64)
        w1 = states[r, n_g:n_g + n].astype(np.int64)
        parent = states[r, n_g + n:].astype(np.int64)
        viol, n_conj = _init_viol(tau, w1, parent, truth_t, n_g, n)
        ps, ns = _sat_counts(viol, w_pos, w_neg)
        out[r] = _log_prior_total(tau, w1, parent, code, p_global, p_eventual, p_part,
                                  n_new) + log_likelihood(ps, ns, n_pos, n_neg, n_conj,
                                                          log_eps, lik_code)
    return out


def split_rhat(traces):
    """Split-R-hat (Gelman et al., BDA3) of a scalar across chains.

    Parameters
    ----------
    traces : ndarray of shape (n_chains, n_draws)

    Returns
    -------
    float
        1.0 when every draw is identical (a chain that never moves off a sharp mode); ``inf``
        when chains sit on different constant values.
    """
    traces = np.asarray(traces, dtype=float)
    n_draws = traces.shape[1]
    half = n_draws // 2
    if half < 2:
        return float("nan")
    split = np.concatenate([traces[:, :half], traces[:, half:2 * half]], axis=0)
    finite = np.isfinite(split)
    if not finite.all():
        return float("nan")
    # The log posterior is tracked incrementally: differences at rounding level are no signal.
    if np.ptp(split) <= 1e-9 * max(1.0, float(np.abs(split).max())):
        return 1.0
    means = split.mean(axis=1)
    within = split.var(axis=1, ddof=1).mean()
    between = half * means.var(ddof=1)
    if within == 0:
        return 1.0 if between == 0 else float("inf")
    var_plus = (half - 1) / half * within + between / half
    return float(np.sqrt(var_plus / within))
