"""Exact posterior by enumeration of the prior's support (globals x eventuals x orders).

A hypothesis' likelihood depends only on how many acceptable and unacceptable demonstrations it
satisfies and on its number of conjuncts, so each part keeps a bitset of the demonstrations it
satisfies and a hypothesis costs one AND and a popcount per 64 demonstrations. The enumeration
streams: a first pass computes the normaliser, a second accumulates clause marginals and keeps
the most probable hypotheses covering all but ``tol`` of the mass.
"""

import math

import numpy as np
from numba import njit

from bsi_sklearn.likelihood import log_likelihood
from bsi_sklearn.priors import count_structures, log_prior_structure, log_prior_subset

__all__ = ["enumerate_structures", "count_hypotheses", "exact_posterior", "ExactResult"]


def count_hypotheses(prior, n_globals, n_subtasks):
    """Number of hypotheses in the prior's support."""
    return count_structures(prior, n_subtasks) * 2**n_globals * 2**n_subtasks


@njit(cache=True)
def _enumerate_structures(n, code):
    # Every parent array with values in {-1} U {other nodes}, kept when it is a forest of the
    # prior's shape. n**n candidates: only called for the small n where exact inference fits.
    total = 1
    for _ in range(n):
        total *= n
    out = np.empty((max(total, 1), n), dtype=np.int64)
    k = 0
    digits = np.zeros(n, dtype=np.int64)
    parent = np.empty(n, dtype=np.int64)
    n_children = np.empty(n, dtype=np.int64)
    for _ in range(total):
        # digit d of node v: 0 -> root, else the d-th other node.
        for v in range(n):
            d = digits[v]
            if d == 0:
                parent[v] = -1
            else:
                parent[v] = d - 1 if d - 1 < v else d
        ok = True
        for v in range(n):  # acyclic: walking up ends within n steps
            a = parent[v]
            steps = 0
            while a >= 0 and steps <= n:
                a = parent[a]
                steps += 1
            if a >= 0:
                ok = False
                break
        if ok and code <= 1:
            n_children[:] = 0
            n_roots = 0
            for v in range(n):
                if parent[v] < 0:
                    n_roots += 1
                else:
                    n_children[parent[v]] += 1
                    if n_children[parent[v]] > 1:
                        ok = False
            if code == 0 and n_roots != 1:
                ok = False
        if ok:
            out[k] = parent
            k += 1
        # increment mixed-radix counter
        for v in range(n):
            digits[v] += 1
            if digits[v] < n:
                break
            digits[v] = 0
    return out[:k]


def enumerate_structures(prior_code, n):
    """All order structures (parent arrays) of a prior's support, shape ``(count, n)``."""
    if n == 0:
        return np.zeros((1, 0), dtype=np.int64)
    return _enumerate_structures(n, prior_code)


@njit(cache=True, nogil=True)
def _popcount64(x):
    x = x - ((x >> np.uint64(1)) & np.uint64(0x5555555555555555))
    x = (x & np.uint64(0x3333333333333333)) + ((x >> np.uint64(2)) & np.uint64(0x3333333333333333))
    x = (x + (x >> np.uint64(4))) & np.uint64(0x0F0F0F0F0F0F0F0F)
    return int((x * np.uint64(0x0101010101010101)) >> np.uint64(56))


@njit(cache=True, nogil=True)
def _subset_tables(clause_bits, first_clause, n_items, p, full):
    # For every subset mask of n_items clauses: demo bitset (AND), size, log prior.
    n_sub = 1 << n_items
    n_words = clause_bits.shape[1]
    bits = np.empty((n_sub, n_words), dtype=np.uint64)
    size = np.zeros(n_sub, dtype=np.int64)
    lp = np.empty(n_sub)
    bits[0, :] = full
    for m in range(1, n_sub):
        low = 0
        while not (m >> low) & 1:
            low += 1
        prev = m & (m - 1)
        for w in range(n_words):
            bits[m, w] = bits[prev, w] & clause_bits[first_clause + low, w]
        size[m] = size[prev] + 1
    for m in range(n_sub):
        lp[m] = log_prior_subset(size[m], n_items, p)
    return bits, size, lp


@njit(cache=True, nogil=True)
def _structure_tables(structures, clause_bits, n_g, n, full, code, p_part, n_new):
    n_s = structures.shape[0]
    n_words = clause_bits.shape[1]
    bits = np.empty((n_s, n_words), dtype=np.uint64)
    size = np.zeros(n_s, dtype=np.int64)
    lp = np.empty(n_s)
    base = n_g + n
    for s in range(n_s):
        parent = structures[s]
        bits[s, :] = full
        for v in range(n):
            a = parent[v]
            while a >= 0:
                c = base + a * n + v
                for w in range(n_words):
                    bits[s, w] &= clause_bits[c, w]
                size[s] += 1
                a = parent[a]
        lp[s] = log_prior_structure(parent, code, p_part, n_new)
    return bits, size, lp


@njit(cache=True, nogil=True)
def _hyp_logpost(s, t, e, s_bits, s_size, s_lp, t_bits, t_size, t_lp, e_bits, e_size, e_lp,
                 pos_mask, neg_mask, n_pos, n_neg, log_eps, lik_code):
    pos_sat = 0
    neg_sat = 0
    for w in range(pos_mask.shape[0]):
        sat = s_bits[s, w] & t_bits[t, w] & e_bits[e, w]
        pos_sat += _popcount64(sat & pos_mask[w])
        neg_sat += _popcount64(sat & neg_mask[w])
    n_conj = s_size[s] + t_size[t] + e_size[e]
    return s_lp[s] + t_lp[t] + e_lp[e] + log_likelihood(
        float(pos_sat), float(neg_sat), float(n_pos), float(n_neg), n_conj, log_eps, lik_code
    )


@njit(cache=True, nogil=True)
def _exact_kernel(s_bits, s_size, s_lp, t_bits, t_size, t_lp, e_bits, e_size, e_lp,
                  pos_mask, neg_mask, n_pos, n_neg, log_eps, lik_code, log_keep):
    n_s, n_t, n_e = s_bits.shape[0], t_bits.shape[0], e_bits.shape[0]
    # Pass 1: log normaliser with a running maximum.
    mx = -np.inf
    acc = 0.0
    for s in range(n_s):
        if s_lp[s] == -np.inf:
            continue
        for t in range(n_t):
            for e in range(n_e):
                lp = _hyp_logpost(s, t, e, s_bits, s_size, s_lp, t_bits, t_size, t_lp,
                                  e_bits, e_size, e_lp, pos_mask, neg_mask, n_pos, n_neg,
                                  log_eps, lik_code)
                if lp == -np.inf:
                    continue
                if lp > mx:
                    acc = acc * math.exp(mx - lp) + 1.0
                    mx = lp
                else:
                    acc += math.exp(lp - mx)
    log_z = mx + math.log(acc)
    # Pass 2: per-part marginal masses, and the hypotheses above the keep threshold.
    mass_s = np.zeros(n_s)
    mass_t = np.zeros(n_t)
    mass_e = np.zeros(n_e)
    cap = 1024
    keep_idx = np.empty((cap, 3), dtype=np.int64)
    keep_lp = np.empty(cap)
    k = 0
    for s in range(n_s):
        if s_lp[s] == -np.inf:
            continue
        for t in range(n_t):
            for e in range(n_e):
                lp = _hyp_logpost(s, t, e, s_bits, s_size, s_lp, t_bits, t_size, t_lp,
                                  e_bits, e_size, e_lp, pos_mask, neg_mask, n_pos, n_neg,
                                  log_eps, lik_code) - log_z
                if lp == -np.inf:
                    continue
                p = math.exp(lp)
                mass_s[s] += p
                mass_t[t] += p
                mass_e[e] += p
                if lp >= log_keep:
                    if k == cap:
                        cap *= 2
                        new_idx = np.empty((cap, 3), dtype=np.int64)
                        new_idx[:k] = keep_idx[:k]
                        keep_idx = new_idx
                        new_lp = np.empty(cap)
                        new_lp[:k] = keep_lp[:k]
                        keep_lp = new_lp
                    keep_idx[k, 0] = s
                    keep_idx[k, 1] = t
                    keep_idx[k, 2] = e
                    keep_lp[k] = lp
                    k += 1
    return log_z, keep_idx[:k], keep_lp[:k], mass_s, mass_t, mass_e


class ExactResult:
    """What the enumeration returns: kept hypotheses, their log posterior, marginals."""

    def __init__(self, structures, tau_masks, w1_masks, log_prob, dropped_mass,
                 clause_marginals, log_evidence, n_hypotheses):
        self.structures = structures          # (H, n) parent arrays
        self.tau_masks = tau_masks            # (H, n_g) bool
        self.w1_masks = w1_masks              # (H, n) bool
        self.log_prob = log_prob              # (H,) normalised log posterior, descending
        self.dropped_mass = dropped_mass
        self.clause_marginals = clause_marginals
        self.log_evidence = log_evidence
        self.n_hypotheses = n_hypotheses


def _mask_bits(masks, n_items):
    return ((masks[:, None] >> np.arange(n_items)) & 1).astype(bool)


def exact_posterior(truth, y01, n_g, n, prior_code, p_global, p_eventual, p_part, n_new,
                    log_eps, lik_code, tol=1e-9):
    """Enumerate the support and return the posterior.

    Parameters
    ----------
    truth : ndarray (n_demos, n_clauses) uint8
        Clause truth matrix (see ``_clauses``).
    y01 : ndarray (n_demos,)
        Labels in {0, 1}.
    n_g, n : int
        Numbers of global candidates and subtasks.
    prior_code, lik_code : int
    p_global, p_eventual, p_part, n_new, log_eps : float
    tol : float
        Posterior mass the result may drop (the least probable hypotheses).

    Returns
    -------
    ExactResult
    """
    from bsi_sklearn.clauses import pack_rows

    n_demos = truth.shape[0]
    clause_bits = pack_rows(np.ascontiguousarray(truth.T))           # (n_clauses, words)
    n_words = clause_bits.shape[1]
    full = pack_rows(np.ones((1, n_demos), dtype=np.uint8))[0]
    pos_mask = pack_rows((y01 == 1).astype(np.uint8)[None, :])[0]
    neg_mask = pack_rows((y01 == 0).astype(np.uint8)[None, :])[0]
    assert n_words == full.shape[0]
    structures = enumerate_structures(prior_code, n)
    s_bits, s_size, s_lp = _structure_tables(structures, clause_bits, n_g, n, full,
                                             prior_code, p_part, n_new)
    t_bits, t_size, t_lp = _subset_tables(clause_bits, 0, n_g, p_global, full)
    e_bits, e_size, e_lp = _subset_tables(clause_bits, n_g, n, p_eventual, full)
    n_hyp = len(structures) * len(t_lp) * len(e_lp)
    log_keep = math.log(tol / n_hyp) if tol > 0 else -np.inf
    log_z, keep_idx, keep_lp, mass_s, mass_t, mass_e = _exact_kernel(
        s_bits, s_size, s_lp, t_bits, t_size, t_lp, e_bits, e_size, e_lp,
        pos_mask, neg_mask, int((y01 == 1).sum()), int((y01 == 0).sum()), log_eps, lik_code,
        log_keep,
    )
    # Smallest prefix of the sorted kept hypotheses that covers 1 - tol.
    order = np.argsort(-keep_lp, kind="stable")
    keep_idx, keep_lp = keep_idx[order], keep_lp[order]
    cum = np.cumsum(np.exp(keep_lp))
    if tol > 0:
        stop = int(np.searchsorted(cum, 1.0 - tol)) + 1
        keep_idx, keep_lp, cum = keep_idx[:stop], keep_lp[:stop], cum[:stop]
    dropped = max(0.0, 1.0 - float(cum[-1])) if len(cum) else 1.0
    # Clause marginals from the per-part masses.
    n_cl = n_g + n + n * n
    marg = np.zeros(n_cl)
    t_ids = np.arange(len(mass_t))
    for j in range(n_g):
        marg[j] = mass_t[((t_ids >> j) & 1).astype(bool)].sum()
    e_ids = np.arange(len(mass_e))
    for w in range(n):
        marg[n_g + w] = mass_e[((e_ids >> w) & 1).astype(bool)].sum()
    for s in np.flatnonzero(mass_s):
        parent = structures[s]
        for v in range(n):
            a = parent[v]
            while a >= 0:
                marg[n_g + n + a * n + v] += mass_s[s]
                a = parent[a]
    return ExactResult(
        structures=structures[keep_idx[:, 0]],
        tau_masks=_mask_bits(keep_idx[:, 1], n_g),
        w1_masks=_mask_bits(keep_idx[:, 2], n),
        log_prob=keep_lp,
        dropped_mass=dropped,
        clause_marginals=marg,
        log_evidence=log_z,
        n_hypotheses=n_hyp,
    )
