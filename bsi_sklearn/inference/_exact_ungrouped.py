"""The ungrouped exact enumeration: every hypothesis, one by one (the reference).

Kept as the reference the grouped engine (:mod:`bsi_sklearn.inference.exact`) is tested against: it
streams every (order structure, global subset, eventual subset) triple twice (normaliser, then
marginals and kept hypotheses), one AND and two popcounts per 64 demonstrations each. It holds
one array over all order structures, so it is for small supports only.
"""

import math
from typing import NamedTuple

import numpy as np
from numba import njit

from bsi_sklearn.inference._exact_parts import PartTable
from bsi_sklearn.model.clauses import clause_index_order, popcount
from bsi_sklearn.model.likelihood import log_likelihood
from bsi_sklearn.model.priors import log_prior_structure

__all__ = ["LabelMasks", "ungrouped_kernel", "structure_tables"]


class LabelMasks(NamedTuple):
    """Which demonstrations are acceptable / unacceptable, as bitsets, and how many."""

    pos: np.ndarray    # (n_words,) uint64
    neg: np.ndarray    # (n_words,) uint64
    n_pos: float
    n_neg: float


@njit(cache=True, nogil=True)
def structure_tables(structures, clause_bits, full, model):
    """Bitset, number of orders and log prior of every order structure given as parent rows."""
    n_s = structures.shape[0]
    n_words = clause_bits.shape[1]
    bits = np.empty((n_s, n_words), dtype=np.uint64)
    size = np.zeros(n_s, dtype=np.int64)
    lp = np.empty(n_s)
    n = model.n
    for s in range(n_s):
        parent = structures[s]
        bits[s, :] = full
        for v in range(n):
            a = parent[v]
            while a >= 0:
                c = clause_index_order(a, v, model.n_g, n)
                for w in range(n_words):
                    bits[s, w] &= clause_bits[c, w]
                size[s] += 1
                a = parent[a]
        lp[s] = log_prior_structure(parent, model)
    return PartTable(bits, size, lp)


@njit(cache=True, nogil=True)
def _hyp_logpost(s, t, e, parts_s, parts_t, parts_e, labels, model):
    return _hyp_logpost_counts(s, t, e, parts_s, parts_t, parts_e, labels, model)[0]


@njit(cache=True, nogil=True)
def _hyp_logpost_counts(s, t, e, parts_s, parts_t, parts_e, labels, model):
    # The log posterior (unnormalised) and the number of misclassified demonstrations.
    pos_sat = 0
    neg_sat = 0
    for w in range(labels.pos.shape[0]):
        sat = parts_s.bits[s, w] & parts_t.bits[t, w] & parts_e.bits[e, w]
        pos_sat += int(popcount(sat & labels.pos[w]))
        neg_sat += int(popcount(sat & labels.neg[w]))
    n_conj = parts_s.size[s] + parts_t.size[t] + parts_e.size[e]
    lp = parts_s.lp[s] + parts_t.lp[t] + parts_e.lp[e] + log_likelihood(
        float(pos_sat), float(neg_sat), labels.n_pos, labels.n_neg, n_conj, model.log_eps,
        model.likelihood, model.flips
    )
    return lp, int(labels.n_pos) - pos_sat + neg_sat


@njit(cache=True, nogil=True)
def ungrouped_kernel(parts_s, parts_t, parts_e, labels, model, log_keep):
    """Log evidence, kept hypotheses (log posterior >= log_keep) and per-part masses.

    Also the posterior mass by number of misclassified demonstrations.
    """
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
    mass_v = np.zeros(int(labels.n_pos + labels.n_neg) + 1)
    cap = 1024
    keep_idx = np.empty((cap, 3), dtype=np.int64)
    keep_lp = np.empty(cap)
    k = 0
    for s in range(n_s):
        if s_lp[s] == -np.inf:
            continue
        for t in range(n_t):
            for e in range(n_e):
                lp, v = _hyp_logpost_counts(s, t, e, parts_s, parts_t, parts_e, labels, model)
                lp -= log_z
                if lp == -np.inf:
                    continue
                p = math.exp(lp)
                mass_v[v] += p
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
    return log_z, keep_idx[:k], keep_lp[:k], mass_s, mass_t, mass_e, mass_v


