"""Exact posterior by enumeration of the prior's support (globals x eventuals x orders).

A hypothesis' likelihood depends only on how many acceptable and unacceptable demonstrations it
satisfies and on its number of conjuncts, so each part keeps a bitset of the demonstrations it
satisfies and a hypothesis costs one AND and a popcount per 64 demonstrations. The enumeration
streams: a first pass computes the normaliser, a second accumulates clause marginals and keeps
the most probable hypotheses covering all but ``tol`` of the mass.
"""

import math
from typing import NamedTuple

import numpy as np
from numba import njit

from bsi_sklearn.clauses import pack_rows
from bsi_sklearn.likelihood import log_likelihood
from bsi_sklearn.priors import log_prior_structure, log_prior_subset, support_structures

__all__ = ["exact_posterior", "ExactResult"]


class PartTable(NamedTuple):
    """One part of the hypotheses (order structures, global subsets or eventual subsets)."""

    bits: np.ndarray   # (n_items, n_words) uint64: the demonstrations each item satisfies
    size: np.ndarray   # (n_items,) int64: its number of conjuncts
    lp: np.ndarray     # (n_items,) float64: its log prior


class LabelMasks(NamedTuple):
    """Which demonstrations are acceptable / unacceptable, as bitsets, and how many."""

    pos: np.ndarray    # (n_words,) uint64
    neg: np.ndarray    # (n_words,) uint64
    n_pos: float
    n_neg: float


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
    return PartTable(bits, size, lp)


@njit(cache=True, nogil=True)
def _structure_tables(structures, clause_bits, full, model):
    n_s = structures.shape[0]
    n_words = clause_bits.shape[1]
    bits = np.empty((n_s, n_words), dtype=np.uint64)
    size = np.zeros(n_s, dtype=np.int64)
    lp = np.empty(n_s)
    n = model.n
    base = model.n_g + n
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
        lp[s] = log_prior_structure(parent, model)
    return PartTable(bits, size, lp)


@njit(cache=True, nogil=True)
def _hyp_logpost(s, t, e, parts_s, parts_t, parts_e, labels, model):
    pos_sat = 0
    neg_sat = 0
    for w in range(labels.pos.shape[0]):
        sat = parts_s.bits[s, w] & parts_t.bits[t, w] & parts_e.bits[e, w]
        pos_sat += _popcount64(sat & labels.pos[w])
        neg_sat += _popcount64(sat & labels.neg[w])
    n_conj = parts_s.size[s] + parts_t.size[t] + parts_e.size[e]
    return parts_s.lp[s] + parts_t.lp[t] + parts_e.lp[e] + log_likelihood(
        float(pos_sat), float(neg_sat), labels.n_pos, labels.n_neg, n_conj, model.log_eps,
        model.likelihood
    )


@njit(cache=True, nogil=True)
def _exact_kernel(parts_s, parts_t, parts_e, labels, model, log_keep):
    s_lp = parts_s.lp
    n_s, n_t, n_e = s_lp.shape[0], parts_t.lp.shape[0], parts_e.lp.shape[0]
    # Pass 1: log normaliser with a running maximum.
    mx = -np.inf
    acc = 0.0
    for s in range(n_s):
        if s_lp[s] == -np.inf:
            continue
        for t in range(n_t):
            for e in range(n_e):
                lp = _hyp_logpost(s, t, e, parts_s, parts_t, parts_e, labels, model)
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
                lp = _hyp_logpost(s, t, e, parts_s, parts_t, parts_e, labels, model) - log_z
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


def exact_posterior(truth, y01, model, tol=1e-9):
    """Enumerate the support and return the posterior.

    Parameters
    ----------
    truth : ndarray (n_demos, n_clauses) uint8
        Clause truth matrix (:func:`bsi_sklearn.clauses.clause_truth`).
    y01 : ndarray (n_demos,)
        Labels in {0, 1}.
    model : Model
        The model bundle (:func:`bsi_sklearn.model.make_model`).
    tol : float
        Posterior mass the result may drop (the least probable hypotheses).

    Returns
    -------
    ExactResult
    """
    n_g, n = model.n_g, model.n
    n_demos = truth.shape[0]
    clause_bits = pack_rows(np.ascontiguousarray(truth.T))           # (n_clauses, words)
    full = pack_rows(np.ones((1, n_demos), dtype=np.uint8))[0]
    labels = LabelMasks(
        pos=pack_rows((y01 == 1).astype(np.uint8)[None, :])[0],
        neg=pack_rows((y01 == 0).astype(np.uint8)[None, :])[0],
        n_pos=float((y01 == 1).sum()), n_neg=float((y01 == 0).sum()),
    )
    structures = support_structures(model)
    parts_s = _structure_tables(structures, clause_bits, full, model)
    parts_t = _subset_tables(clause_bits, 0, n_g, model.p_global, full)
    parts_e = _subset_tables(clause_bits, n_g, n, model.p_eventual, full)
    n_hyp = len(structures) * len(parts_t.lp) * len(parts_e.lp)
    log_keep = math.log(tol / n_hyp) if tol > 0 else -np.inf
    log_z, keep_idx, keep_lp, mass_s, mass_t, mass_e = _exact_kernel(
        parts_s, parts_t, parts_e, labels, model, log_keep)
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
