"""The Gibbs moves of one MCMC chain, each an exact update of its block (no Hastings ratio).

- :func:`flip_move`: one inclusion bit of tau or W1;
- :func:`chain_move` (Priors 1, 2): take a subtask out of its chain and re-insert it at any
  position of any chain, or as a new chain where the prior allows one, drawing its eventual
  bit ``F(v)`` jointly with its place;
- :func:`forest_move` (Prior 3): prune the subtree under a subtask and regraft it anywhere
  outside it, or as a new root, drawing the subtask's eventual bit jointly with the place.

Every candidate is weighted by prior x likelihood^beta: ``beta`` is the inverse temperature of
the replica being moved (1 for the target posterior; parallel tempering runs hotter replicas).
The structure moves draw the eventual bit with the place because the two are tied: an order
``(!b U a)`` holds only where ``a`` happens, so a demonstration that never completes ``a``
violates ``F(a)`` and every order into ``a`` at once, and dropping either alone gains nothing.

The moves read the model bundle (:class:`bsi_sklearn.model.Model`), the deduplicated
demonstrations (``_chain_kernel.Demos``) and the chain's scratch buffers
(``_chain_kernel.ChainBuffers``), and update the per-demonstration count of
violated clauses in place.

The three moves are inlined into the chain kernel at numba's level: as calls, passing the
bundles' arrays cost 10-15% of a Prior 3 chain.
"""

import math

import numpy as np
from numba import njit

from bsi_sklearn.inference._row_counts import bit_sums, flip_masks, mask_sums, zero_mask
from bsi_sklearn.model.clauses import clause_index_eventual, clause_index_order
from bsi_sklearn.model.likelihood import log_likelihood, log_likelihood_cb
from bsi_sklearn.model.priors import subset_inclusion

__all__ = ["add_pair", "draw", "flip_move", "chain_move", "chain_candidates", "chain_apply",
           "forest_move", "forest_candidates", "forest_apply"]


@njit(cache=True, nogil=True)
def draw(lw, k, u, ew):
    """Index ``i < k`` drawn with probability proportional to ``exp(lw[i])``."""
    # Sample index i < k with probability proportional to exp(lw[i]), from a uniform u in
    # [0, 1); ew is scratch space (each weight is exponentiated once).
    mx = -np.inf
    for i in range(k):
        if lw[i] > mx:
            mx = lw[i]
    total = 0.0
    for i in range(k):
        # exp of anything below -746 is 0.0: skip the call (most candidates of a peaked
        # posterior), the same numbers either way.
        x = lw[i] - mx
        ew[i] = math.exp(x) if x > -746.0 else 0.0
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
def add_pair(viol, truth_t, c, sign):
    """Add ``sign`` to the violation count of every row where clause ``c`` is false."""
    for d in range(viol.shape[0]):
        viol[d] += sign if truth_t[c, d] == 0 else 0


@njit(cache=True, nogil=True, inline="always")
def flip_move(c, inc, lp_in, lp_out, viol, masks, n_conj, demos, model, u, beta):
    """Gibbs update of inclusion bit ``c``: ``(new bit, log-likelihood, uniform used)``.

    ``masks``: :func:`flip_masks` of ``viol``, kept up to date here.
    """
    # Gibbs update of one inclusion bit at inverse temperature beta: returns the new bit, the
    # new (untempered) log-likelihood and whether the uniform u was used (only when both
    # outcomes are possible).
    truth_t = demos.truth_t
    ps_out, ns_out, ps_in, ns_in = mask_sums(masks, c, inc, demos)
    n_out = n_conj - inc
    ll_out = log_likelihood(ps_out, ns_out, demos.n_pos, demos.n_neg, n_out, model.log_eps,
                            model.likelihood, model.flips)
    ll_in = log_likelihood(ps_in, ns_in, demos.n_pos, demos.n_neg, n_out + 1, model.log_eps,
                           model.likelihood, model.flips)
    lw_out = lp_out + beta * ll_out
    lw_in = lp_in + beta * ll_in
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
        add_pair(viol, truth_t, c, np.int64(1 if new else -1))
        flip_masks(viol, masks)
    return new, (ll_in if new else ll_out), used


@njit(cache=True, nogil=True, inline="always")
def _eventual_inclusion(v, w1, model):
    # F(v)'s log prior weights in and out, the other W1 bits as they are.
    k_others = 0
    for u in range(w1.shape[0]):
        if u != v:
            k_others += w1[u]
    return subset_inclusion(k_others, w1.shape[0], model.p_eventual)


@njit(cache=True, nogil=True, inline="always")
def _push_pair(bufs, k, lp, sums, n_conj, demos, model, beta, le_in, le_out):
    # Two candidates of a structure move at one place: k without F(v), k + 1 with it.
    # sums = (ps_out, ns_out, ps_in, ns_in) from flip_sums; n_conj excludes F(v);
    # (le_in, le_out): F(v)'s inclusion weights (:func:`_eventual_inclusion`), once per move.
    if model.likelihood == 0:  # CB, its log1p by number of conjuncts from the table
        ll_out = log_likelihood_cb(sums[0], sums[1], demos.n_pos, demos.n_neg, n_conj,
                                   model.log_eps, bufs.cb_rejected[n_conj])
        ll_in = log_likelihood_cb(sums[2], sums[3], demos.n_pos, demos.n_neg, n_conj + 1,
                                  model.log_eps, bufs.cb_rejected[n_conj + 1])
    else:
        ll_out = log_likelihood(sums[0], sums[1], demos.n_pos, demos.n_neg, n_conj,
                                model.log_eps, model.likelihood, model.flips)
        ll_in = log_likelihood(sums[2], sums[3], demos.n_pos, demos.n_neg, n_conj + 1,
                               model.log_eps, model.likelihood, model.flips)
    bufs.cand_lp[k] = lp
    bufs.cand_lp[k + 1] = lp
    bufs.cand_ll[k] = ll_out
    bufs.cand_ll[k + 1] = ll_in
    bufs.lw[k] = lp + le_out + beta * ll_out
    bufs.lw[k + 1] = lp + le_in + beta * ll_in


@njit(cache=True, nogil=True, inline="always")
def chain_move(v, parent, w1, viol, n_conj, demos, model, bufs, unif, beta):
    """Gibbs re-insertion of subtask ``v`` with its bit ``w1[v]`` (Priors 1, 2).

    Returns ``(N, log prior of the structure, log-likelihood, candidates, the one drawn)``;
    ``w1[v]`` is updated in place; ``bufs.lw[:candidates]`` holds the candidates' weights.
    """
    n_conj, k = chain_candidates(v, parent, w1, viol, n_conj, demos, model, bufs, beta)
    j = draw(bufs.lw, k, unif, bufs.cand_ew)
    n_conj = chain_apply(j, v, parent, w1, viol, n_conj, demos, model, bufs)
    return n_conj, bufs.cand_lp[j], bufs.cand_ll[j], k, j


@njit(cache=True, nogil=True, inline="always")
def chain_candidates(v, parent, w1, viol, n_conj, demos, model, bufs, beta):
    """Take subtask ``v`` and ``F(v)`` out (in place) and weigh every place to put them back.

    Returns ``(N without them, candidates)``: candidate ``i`` puts ``v`` at position
    ``bufs.cand_pos[i]`` of the chain headed by ``bufs.cand_head[i]`` (``-1``: a new chain),
    with ``F(v)`` when ``i`` is odd; ``bufs.lw``, ``cand_lp`` and ``cand_ll`` hold its weight
    at ``beta``, its structure's log prior and its log-likelihood; ``bufs.child`` the
    successors without ``v``.
    """
    # Priors 1 / 2: take v (and F(v)) out and redraw its place among every position of every
    # remaining chain and a new chain (a candidate only where the prior has such structures),
    # each with F(v) left out or put in.
    truth_t = demos.truth_t
    n = model.n
    cv = clause_index_eventual(v, model.n_g)
    le_in, le_out = _eventual_inclusion(v, w1, model)
    lp_chains = model.lp_chains
    cand_head, cand_pos, child = bufs.cand_head, bufs.cand_pos, bufs.child
    if w1[v]:
        add_pair(viol, truth_t, cv, np.int64(-1))
        n_conj -= 1
    for u in range(n):
        child[u] = -1
    for u in range(n):
        if parent[u] >= 0:
            child[parent[u]] = u
    # Remove v's pairs: (ancestor, v) and (v, descendant).
    a = parent[v]
    while a >= 0:
        add_pair(viol, truth_t, clause_index_order(a, v, model.n_g, n), np.int64(-1))
        n_conj -= 1
        a = parent[a]
    d_ = child[v]
    while d_ >= 0:
        add_pair(viol, truth_t, clause_index_order(v, d_, model.n_g, n), np.int64(-1))
        n_conj -= 1
        d_ = child[d_]
    if child[v] >= 0:
        parent[child[v]] = parent[v]
    if parent[v] >= 0:
        child[parent[v]] = child[v]
    parent[v] = -1
    child[v] = -1
    # Candidates: every position of every remaining chain, plus a new chain; two each, weighed
    # over the rows that violate nothing without v (zmask), as bitsets: at position p of a
    # chain u_1 .. u_L, v follows u_1 .. u_p (acc: AND of their (u -> v) clauses) and
    # precedes the rest (suf[p]: zmask AND their (v -> u) clauses).
    bits, zmask, suf, acc, ones = demos.bits, bufs.zmask, bufs.suf, bufs.acc, bufs.ones
    n_words = bits.shape[1]
    zero_mask(viol, zmask)
    members = bufs.members
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
        while u >= 0:
            members[L] = u
            L += 1
            u = child[u]
        for w in range(n_words):
            suf[L, w] = zmask[0, w]
            acc[0, w] = ones[0, w]
        for i in range(L - 1, -1, -1):
            c = clause_index_order(v, members[i], model.n_g, n)
            for w in range(n_words):
                suf[i, w] = suf[i + 1, w] & bits[c, w]
        lp = lp_chains[m_rem]
        for p in range(L + 1):
            sums = bit_sums(suf, p, acc, 0, bits, cv, demos)
            _push_pair(bufs, k, lp, sums, n_conj + L, demos, model, beta, le_in, le_out)
            for i in range(2):
                cand_head[k + i] = h
                cand_pos[k + i] = p
            k += 2
            if p < L:
                c = clause_index_order(members[p], v, model.n_g, n)
                for w in range(n_words):
                    acc[0, w] &= bits[c, w]
    if lp_chains[m_rem + 1] > -np.inf or k == 0:
        sums = bit_sums(zmask, 0, ones, 0, bits, cv, demos)
        _push_pair(bufs, k, lp_chains[m_rem + 1], sums, n_conj, demos, model, beta,
                   le_in, le_out)
        for i in range(2):
            cand_head[k + i] = -1
            cand_pos[k + i] = 0
        k += 2
    return n_conj, k


@njit(cache=True, nogil=True, inline="always")
def chain_apply(j, v, parent, w1, viol, n_conj, demos, model, bufs):
    """Put ``v`` back as candidate ``j`` of :func:`chain_candidates` says; returns ``N``."""
    truth_t = demos.truth_t
    n = model.n
    child = bufs.child
    inc = j & 1
    w1[v] = inc
    if inc:
        add_pair(viol, truth_t, clause_index_eventual(v, model.n_g), np.int64(1))
        n_conj += 1
    h = bufs.cand_head[j]
    if h < 0:
        return n_conj
    p = bufs.cand_pos[j]
    u = h
    prev = -1
    i = 0
    while u >= 0:
        if i < p:
            add_pair(viol, truth_t, clause_index_order(u, v, model.n_g, n), np.int64(1))
        else:
            add_pair(viol, truth_t, clause_index_order(v, u, model.n_g, n), np.int64(1))
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
    return n_conj


@njit(cache=True, nogil=True, inline="always")
def forest_move(v, parent, w1, viol, n_conj, demos, model, bufs, unif, beta):
    """Gibbs prune-and-regraft of subtask ``v`` with its bit ``w1[v]`` (Prior 3).

    Returns ``(N, log prior of the structure, log-likelihood, candidates, the one drawn)``;
    ``w1[v]`` is updated in place; ``bufs.lw[:candidates]`` holds the candidates' weights.
    """
    n_conj, k, size_s = forest_candidates(v, parent, w1, viol, n_conj, demos, model, bufs,
                                          beta)
    j = draw(bufs.lw, k, unif, bufs.cand_ew)
    n_conj = forest_apply(j, v, size_s, parent, w1, viol, n_conj, demos, model, bufs)
    return n_conj, bufs.cand_lp[j], bufs.cand_ll[j], k, j


@njit(cache=True, nogil=True, inline="always")
def forest_candidates(v, parent, w1, viol, n_conj, demos, model, bufs, beta):
    """Prune the subtree under ``v`` and ``F(v)`` (in place) and weigh every regraft.

    Returns ``(N without them, candidates, the subtree's size)``: candidate ``i`` makes
    ``bufs.cand_head[i]`` the parent of ``v`` (``-1``: a root), with ``F(v)`` when ``i`` is
    odd; ``bufs.lw``, ``cand_lp`` and ``cand_ll`` as for :func:`chain_candidates`;
    ``bufs.in_s`` marks the subtree.
    """
    # Prior 3: prune the subtree rooted at v and regraft it anywhere outside it, with F(v)
    # left out or put in.
    truth_t = demos.truth_t
    n = model.n
    cv = clause_index_eventual(v, model.n_g)
    le_in, le_out = _eventual_inclusion(v, w1, model)
    g, g_const = model.forest_g, model.forest_const
    cand_head, in_s, size = bufs.cand_head, bufs.in_s, bufs.size
    if w1[v]:
        add_pair(viol, truth_t, cv, np.int64(-1))
        n_conj -= 1
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
                add_pair(viol, truth_t, clause_index_order(a, s, model.n_g, n), np.int64(-1))
                n_conj -= 1
        a = parent[a]
    parent[v] = -1
    # anc[a]: the rows that satisfy every (a -> s) clause, s in the subtree, i.e. those a
    # keeps satisfied as an ancestor of the whole subtree; candidates are weighed over the
    # rows that violate nothing once it is pruned (zmask), as bitsets.
    bits, zmask, anc, acc, ones = demos.bits, bufs.zmask, bufs.anc, bufs.acc, bufs.ones
    n_words = bits.shape[1]
    zero_mask(viol, zmask)
    for a in range(n):
        if in_s[a]:
            continue
        for w in range(n_words):
            anc[a, w] = ones[0, w]
        for s in range(n):
            if in_s[s]:
                c = clause_index_order(a, s, model.n_g, n)
                for w in range(n_words):
                    anc[a, w] &= bits[c, w]
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
        for w in range(n_words):
            acc[0, w] = zmask[0, w]
        depth = 0
        lp = lp_cut
        a = u
        while a >= 0:
            for w in range(n_words):
                acc[0, w] &= anc[a, w]
            lp += g[size[a] + size_s] - g[size[a]]
            depth += 1
            a = parent[a]
        sums = bit_sums(acc, 0, ones, 0, bits, cv, demos)
        _push_pair(bufs, k, lp, sums, n_conj + depth * size_s, demos, model, beta, le_in,
                   le_out)
        cand_head[k] = u
        cand_head[k + 1] = u
        k += 2
    return n_conj, k, size_s


@njit(cache=True, nogil=True, inline="always")
def forest_apply(j, v, size_s, parent, w1, viol, n_conj, demos, model, bufs):
    """Regraft as candidate ``j`` of :func:`forest_candidates` says; returns ``N``."""
    truth_t = demos.truth_t
    n = model.n
    in_s = bufs.in_s
    inc = j & 1
    w1[v] = inc
    if inc:
        add_pair(viol, truth_t, clause_index_eventual(v, model.n_g), np.int64(1))
        n_conj += 1
    u = bufs.cand_head[j]
    parent[v] = u
    a = u
    while a >= 0:
        for s in range(n):
            if in_s[s]:
                add_pair(viol, truth_t, clause_index_order(a, s, model.n_g, n), np.int64(1))
        n_conj += size_s
        a = parent[a]
    return n_conj
