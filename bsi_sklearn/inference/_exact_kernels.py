"""The numba passes of the grouped exact enumeration (:mod:`bsi_sklearn.inference.exact`).

The passes run over pairs (structure group, subset-pair group). A pair's likelihood depends on
(satisfied positives ``ps``, satisfied negatives ``ns``, conjuncts ``k``) only
(:class:`Likelihoods`: a sum ``lik_pos[k, ps] + lik_neg[k, ns]`` for CB and CI, a joint table
of ``(ps, ns)`` for the likelihoods that are not a sum). Pairs that cannot matter are skipped
with a bound: a pair's ``ps`` is at most the positives both groups satisfy, so its likelihood
is at most ``bound[k, min(P_g, P_h)]`` (the largest over every ``ns`` and every ``ps`` up to
it); whenever that bound, times the whole prior mass, is below ``exp(margin)`` times the
evidence found so far, the pair and every later one of its size class (groups are sorted by
decreasing ``P_g``) are skipped. What they drop is below ``exp(margin)`` of the evidence
(``margin <= log(1e-16)``), and never holds a hypothesis above the keep threshold.
"""

import math
from typing import NamedTuple

import numpy as np
from numba import njit

from bsi_sklearn._jit import helper
from bsi_sklearn.model.clauses import popcount, popcounts
from bsi_sklearn.model.likelihood import depends_on_conjuncts, log_likelihood, splits_by_label

__all__ = ["StructureSide", "SubsetSide", "Likelihoods", "likelihood_tables", "pair_ll",
           "pair_ll_many", "pair_lls", "group_pair_lls", "log_evidence", "group_masses",
           "MAX_CELLS"]

#: Largest (satisfied positives x satisfied negatives) table of the passes' caches; above it
#: every pair of groups pays a log and an exp instead.
MAX_CELLS = 1 << 22


class StructureSide(NamedTuple):
    """Structure groups sorted by (size, decreasing satisfied positives)."""

    bits: np.ndarray       # (G, n_words) uint64
    weight: np.ndarray     # (G,) prior weight relative to exp(ref)
    best: np.ndarray       # (G,) largest member log prior (absolute)
    n_pos: np.ndarray      # (G,) positives the group satisfies
    size: np.ndarray       # (G,) number of orders
    cls_start: np.ndarray  # (C + 1,) size classes: groups cls_start[c]:cls_start[c + 1]
    cls_size: np.ndarray   # (C,) the class' number of orders


class SubsetSide(NamedTuple):
    """Subset-pair groups, sorted by decreasing satisfied positives."""

    pos: np.ndarray        # (H, n_words) bitset AND acceptable demonstrations
    neg: np.ndarray        # (H, n_words) bitset AND unacceptable demonstrations
    size: np.ndarray       # (H,) conjuncts
    lw: np.ndarray         # (H,) log prior weight (absolute)
    best: np.ndarray       # (H,) largest member log prior
    n_pos: np.ndarray      # (H,) positives the group satisfies


class Likelihoods(NamedTuple):
    """``log L`` of a pair by (conjuncts k, satisfied positives ps, satisfied negatives ns).

    ``bound[k, p] >= log L`` whenever ``ps <= p``, whatever ``ns``. A likelihood that is a sum
    (CB, CI) is ``pos[k, ps] + neg[k, ns]`` and ``joint`` is empty; any other is
    ``joint[min(k, K - 1), ps, ns]`` (``K = 1`` when it does not depend on ``k``), or, when
    that table would pass :data:`MAX_CELLS`, computed from the counts (``joint`` of shape
    ``(K, 0, 0)``). Read it with :func:`pair_ll`.
    """

    pos: np.ndarray        # (max_conj + 1, n_pos + 1), or (1, 1) unused
    neg: np.ndarray        # (max_conj + 1, n_neg + 1), or (1, 1) unused
    bound: np.ndarray      # (max_conj + 1, n_pos + 1)
    joint: np.ndarray      # (K, n_pos + 1, n_neg + 1); (0, 1, 1) for a sum
    n_pos: int
    n_neg: int
    log_eps: float         # the model's likelihood parameters, for the counts' path
    code: int
    flips: np.ndarray      # the flip rate's log marginals by misclassified count (codes 2, 4)


@njit(cache=True, nogil=True)
def pair_ll(lik, k, ps, ns):
    """The log-likelihood of a pair of groups with ``k`` conjuncts, ``ps`` / ``ns`` satisfied."""
    if lik.joint.shape[0] == 0:
        return lik.pos[k, ps] + lik.neg[k, ns]
    kk = min(k, lik.joint.shape[0] - 1)
    if lik.joint.shape[1] > 0:
        return lik.joint[kk, ps, ns]
    return _joint_ll(lik, k, ps, ns)


@helper
def _joint_ll(lik, k, ps, ns):
    if k == 0 and (ps < lik.n_pos or ns < lik.n_neg):
        return -np.inf  # no conjunct: every demonstration satisfies it
    return log_likelihood(float(ps), float(ns), float(lik.n_pos), float(lik.n_neg), k,
                          lik.log_eps, lik.code, lik.flips)


def pair_ll_many(lik, k, ps, ns):
    """:func:`pair_ll` of arrays of pairs (for the Python side)."""
    out = np.empty(k.shape[0])
    _pair_ll_many(lik, k, ps, ns, out)
    return out


def pair_lls(lik, k, ps, ns):
    """:func:`pair_ll` of arrays of pairs, in numpy where a table holds it.

    A call into numba per structure group would cost more than the lookups.
    """
    if lik.joint.shape[0] == 0:
        return lik.pos[k, ps] + lik.neg[k, ns]
    if lik.joint.shape[1] > 0:
        return lik.joint[np.minimum(k, lik.joint.shape[0] - 1), ps, ns]
    return pair_ll_many(lik, k.astype(np.int64), ps.astype(np.int64), ns.astype(np.int64))


def group_pair_lls(ss, g, hs, lik):
    """The log-likelihood of structure group ``g`` with every subset-pair group (numpy)."""
    ps = popcounts(hs.pos, ss.bits[g])
    ns = popcounts(hs.neg, ss.bits[g])
    return pair_lls(lik, ss.size[g] + hs.size, ps, ns)


@njit(cache=True, nogil=True)
def _pair_ll_many(lik, k, ps, ns, out):
    for i in range(k.shape[0]):
        out[i] = pair_ll(lik, k[i], ps[i], ns[i])


@helper
def _counts(s_bits, g, h_pos, h_neg, h):
    ps = 0
    ns = 0
    for w in range(s_bits.shape[1]):
        ps += popcount(s_bits[g, w] & h_pos[h, w])
        ns += popcount(s_bits[g, w] & h_neg[h, w])
    return int(ps), int(ns)


def likelihood_tables(n_pos, n_neg, max_conj, model):
    """The likelihood of a pair of groups by its counts, and its bound (:class:`Likelihoods`)."""
    if splits_by_label(model.likelihood):
        pos, neg = np.empty((max_conj + 1, n_pos + 1)), np.empty((max_conj + 1, n_neg + 1))
        bound = np.empty((max_conj + 1, n_pos + 1))
        _sum_tables(n_pos, n_neg, max_conj, model, pos, neg, bound)
        joint = np.empty((0, 1, 1))
    else:
        n_k = max_conj + 1 if depends_on_conjuncts(model.likelihood) else 1
        cells = float(n_k) * (n_pos + 1) * (n_neg + 1)
        joint = np.empty((n_k, n_pos + 1, n_neg + 1) if cells <= MAX_CELLS else (n_k, 0, 0))
        pos = neg = np.zeros((1, 1))
        bound = np.empty((max_conj + 1, n_pos + 1))
    lik = Likelihoods(pos, neg, bound, joint, int(n_pos), int(n_neg), float(model.log_eps),
                      int(model.likelihood), model.flips)
    if joint.shape[0] > 0:
        _fill_joint(lik, max_conj, np.empty((joint.shape[0], n_pos + 1)))
    return lik


@njit(cache=True, nogil=True)
def _fill_joint(lik, max_conj, rows):
    # The joint table (when it has room) and the bound: the best over every ns, then a running
    # best over ps. A table for every k (K = 1) is the likelihood of k >= 1 conjuncts: with
    # none, only (n_pos, n_neg) can occur, where the two agree.
    n_k = lik.joint.shape[0]
    for kk in range(n_k):
        for ps in range(lik.n_pos + 1):
            top = -np.inf
            for ns in range(lik.n_neg + 1):
                v = _joint_ll(lik, kk if n_k > 1 else 1, ps, ns)
                if lik.joint.shape[1] > 0:
                    lik.joint[kk, ps, ns] = v
                top = max(top, v)
            rows[kk, ps] = top
    for k in range(max_conj + 1):
        run = -np.inf
        for ps in range(lik.n_pos + 1):
            run = max(run, rows[min(k, n_k - 1), ps])
            lik.bound[k, ps] = run


@njit(cache=True, nogil=True)
def _sum_tables(n_pos, n_neg, max_conj, model, lik_pos, lik_neg, bound):
    for k in range(max_conj + 1):
        top = -np.inf
        for ns in range(n_neg + 1):
            if k == 0 and ns < n_neg:
                lik_neg[k, ns] = -np.inf  # no conjunct: every demonstration satisfies it
            else:
                lik_neg[k, ns] = log_likelihood(0.0, float(ns), 0.0, float(n_neg), k,
                                                model.log_eps, model.likelihood, model.flips)
            top = max(top, lik_neg[k, ns])
        run = -np.inf
        for ps in range(n_pos + 1):
            lik_pos[k, ps] = log_likelihood(float(ps), 0.0, float(n_pos), 0.0, k,
                                            model.log_eps, model.likelihood, model.flips)
            run = max(run, lik_pos[k, ps] + top)
            bound[k, ps] = run


@njit(cache=True, nogil=True, inline="always")
def _lse_add(mx, acc, v):
    # Streaming log-sum-exp: (mx, acc) holds exp(mx) * acc.
    if v > mx:
        return v, acc * math.exp(mx - v) + 1.0
    if v > -np.inf:
        return mx, acc + math.exp(v - mx)
    return mx, acc


def _cells(lik):
    # Whether the passes cache over (satisfied positives, satisfied negatives) cells, and the
    # size of their scratch (decided here: numba would read MAX_CELLS as it was compiled).
    n_cells = (lik.n_pos + 1) * (lik.n_neg + 1)
    return (n_cells, True) if n_cells <= MAX_CELLS else (1, False)


def log_evidence(ss, hs, lik, cut_offset, cut_floor):
    """Log of the sum over pairs of groups of weight x likelihood.

    Relative to the structure weights' ref. A pair is skipped when its bound is below the
    running sum + ``cut_offset`` or below ``cut_floor``.
    """
    n, use_hist = _cells(lik)
    return _log_evidence(ss, hs, lik, float(cut_offset), float(cut_floor), use_hist,
                         np.empty(ss.weight.shape[0]), np.zeros(n), np.zeros(n, dtype=np.int64),
                         np.empty(n, dtype=np.int64))


@njit(cache=True, nogil=True)
def _log_evidence(ss, hs, lik, cut_offset, cut_floor, use_hist, log_w, hist, stamp, touched):
    n_neg1 = lik.n_neg + 1
    for g in range(log_w.shape[0]):  # numba's log: numpy's may differ in the last bit
        log_w[g] = math.log(ss.weight[g])
    cur = 0
    mx = -np.inf
    acc = 0.0
    for h in range(hs.pos.shape[0]):
        p_h = hs.n_pos[h]
        for c in range(ss.cls_size.shape[0]):
            k = ss.cls_size[c] + hs.size[h]
            cut = cut_floor
            if acc > 0.0:
                cut = max(cut, mx + math.log(acc) + cut_offset)
            cur += 1
            nt = 0
            for g in range(ss.cls_start[c], ss.cls_start[c + 1]):
                if lik.bound[k, min(ss.n_pos[g], p_h)] < cut:
                    break
                ps, ns = _counts(ss.bits, g, hs.pos, hs.neg, h)
                if use_hist:
                    cell = ps * n_neg1 + ns
                    if stamp[cell] != cur:
                        stamp[cell] = cur
                        hist[cell] = 0.0
                        touched[nt] = cell
                        nt += 1
                    hist[cell] += ss.weight[g]
                else:
                    mx, acc = _lse_add(mx, acc, log_w[g] + pair_ll(lik, k, ps, ns) + hs.lw[h])
            for i in range(nt):
                cell = touched[i]
                ps = cell // n_neg1
                ns = cell - ps * n_neg1
                mx, acc = _lse_add(mx, acc, math.log(hist[cell]) + pair_ll(lik, k, ps, ns)
                                   + hs.lw[h])
    return mx + math.log(acc)


def group_masses(ss, hs, lik, log_z, keep, cut):
    """Posterior masses of the groups and by misclassified demonstrations, and flags.

    ``mass_s``, ``mass_h``: the mass of every structure group and subset-pair group.
    The flags say which structure groups may hold a kept hypothesis. ``mass_v[v]`` is the
    (normalised) mass of the hypotheses that violate ``v - ns`` acceptable demonstrations and
    satisfy ``ns`` unacceptable ones (``v = n_pos - ps + ns``).

    ``log_z`` is relative to the structure weights' ref. A structure group is flagged when,
    with some subset-pair group, its best member may reach ``keep`` (absolute log posterior,
    unnormalised). Pairs whose bound is below ``cut`` are skipped, as in :func:`log_evidence`.
    """
    out = (np.zeros(ss.weight.shape[0]), np.zeros(hs.pos.shape[0]),
           np.zeros(ss.weight.shape[0], dtype=np.uint8), np.zeros(lik.n_pos + lik.n_neg + 1))
    n, use_cache = _cells(lik)
    _group_masses(ss, hs, lik, float(log_z), float(keep), float(cut), use_cache, out,
                  (np.zeros(n, dtype=np.int64), np.empty(n), np.empty(n)))
    return out


@njit(cache=True, nogil=True)
def _group_masses(ss, hs, lik, log_z, keep, cut, use_cache, out, cache):
    mass_s, mass_h, flag, mass_v = out
    stamp, factor, cell_ll = cache
    n_neg1 = lik.n_neg + 1
    cur = 0
    for h in range(hs.pos.shape[0]):
        off = hs.lw[h] - log_z
        keep_h = keep - hs.best[h]
        p_h = hs.n_pos[h]
        mh = 0.0
        for c in range(ss.cls_size.shape[0]):
            k = ss.cls_size[c] + hs.size[h]
            cur += 1
            for g in range(ss.cls_start[c], ss.cls_start[c + 1]):
                if lik.bound[k, min(ss.n_pos[g], p_h)] < cut:
                    break
                ps, ns = _counts(ss.bits, g, hs.pos, hs.neg, h)
                if use_cache:
                    cell = ps * n_neg1 + ns
                    if stamp[cell] != cur:
                        stamp[cell] = cur
                        cell_ll[cell] = pair_ll(lik, k, ps, ns)
                        factor[cell] = math.exp(cell_ll[cell] + off)
                    ll = cell_ll[cell]
                    p = ss.weight[g] * factor[cell]
                else:
                    ll = pair_ll(lik, k, ps, ns)
                    p = ss.weight[g] * math.exp(ll + off)
                mass_s[g] += p
                mass_v[lik.n_pos - ps + ns] += p
                mh += p
                if ss.best[g] + ll >= keep_h:
                    flag[g] = 1
        mass_h[h] = mh
