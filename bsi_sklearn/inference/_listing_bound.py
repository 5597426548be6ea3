"""A lower bound on the grouped enumeration's listing, known before its dear tables.

The grouped engine (:mod:`bsi_sklearn.inference.exact`) first groups the order structures that
satisfy every acceptable demonstration (cheap: few survive), then again every structure that
may matter (often most of an attempt's time), and only after the passes over those groups
knows how many hypotheses it would list. This module bounds that number from below with what
the first grouping gives, so that ``inference="auto"`` can give up before the second one when
even the bound's listing is over the work budget (the decision is then the one the full
attempt would have reached).

Why the bound holds. Write ``A`` for the hypotheses whose structure satisfies every acceptable
demonstration (the first grouping's), ``R`` for the rest, ``Z`` for the evidence and ``keep``
``= log_keep + log Z`` for the listing's threshold (``exact_posterior``'s ``log(tol / n_hyp)``).

1. ``Z <= U`` (:func:`log_evidence_upper`): ``A``'s part is the first pass' evidence, which
   skipped pairs of groups only when they hold less than ``exp(margin)`` of it, so it is at most
   ``z_A * (1 + exp(margin))``. A structure of ``R`` satisfies at most ``n_pos - 1`` acceptable
   demonstrations, so with subset-pair group ``h`` (``P_h`` of them, ``k_h`` conjuncts) a pair
   satisfies at most ``min(n_pos - 1, P_h)`` and has at least ``k_h`` conjuncts: its log
   likelihood is at most ``c_h = max_{k >= k_h} bound[k, min(n_pos - 1, P_h)]``
   (:class:`~bsi_sklearn.inference._exact_kernels.Likelihoods`: ``bound[k, p]`` is the largest
   over every ``ps <= p`` and every ``ns``). ``R``'s prior mass is ``1 - P_A`` (the structure
   prior sums to one over the support), so ``R``'s part is at most
   ``(1 - P_A) * sum_h W_h exp(c_h)``.
2. Every hypothesis of posterior score ``lp >= keep`` is counted by the listing (its pair of
   groups is never skipped, its structure group is flagged, its subset-pair group passes the
   listing's test, since each group's best member bounds its own), so the listing's size
   ``n_list`` is at least ``#{lp >= keep} >= #{phi in A: lp >= log_keep + U}``.
3. In a pair of groups ``(g, h)`` of ``A`` with ``m`` members, summed prior ``W``, best member's
   log prior ``b`` and log likelihood ``ll``, count the members of log prior at least
   ``x = log_keep + U - ll``: those below sum to less than ``m exp(x)`` and those above to at
   most ``c exp(b)`` each, so ``c >= (W - m exp(x)) / exp(b)``; and ``c >= 1`` when ``b >= x``
   (the best member).
4. The listing charges every hypothesis it may list ``item_cost``, and every structure of a
   flagged group ``structure_cost`` plus one per subset-pair group it passes. A first-grouping
   group is a group of the second grouping too (same key, same members: every structure of its
   key satisfies every acceptable demonstration), and it is flagged, with every subset-pair
   group of a counted hypothesis passed, as soon as one of its pairs holds a counted
   hypothesis. :func:`listing_work_lower_bound` sums those charges over the counts of step 3.

Each step leaves a relative slack of ``1e-9`` against rounding (every comparison is made a
little harder to pass, every sum a little smaller), so the bound stays below the count that
the engine's own floating-point arithmetic gives. Plain numpy over the first grouping's pairs
(a few thousand): milliseconds.
"""

import math

import numpy as np

from bsi_sklearn.inference._exact_kernels import group_pair_lls

__all__ = ["log_evidence_upper", "listing_work_lower_bound", "SLACK"]

#: Relative slack against rounding in every step of the bound.
SLACK = 1e-9


def log_evidence_upper(log_z_a, log_prior_a, hs, lik, n_pos, margin):
    """An upper bound of the log evidence from the first grouping (step 1 of the module).

    Parameters
    ----------
    log_z_a : float
        Log evidence (absolute) of the hypotheses whose structure satisfies all ``n_pos``
        acceptable demonstrations, as the first pass found it (skipping at most ``exp(margin)``
        of it).
    log_prior_a : float
        Log prior mass of those structures.
    hs : SubsetSide
    lik : Likelihoods
    n_pos : int
        Acceptable demonstrations (at least one).
    margin : float

    Returns
    -------
    float
    """
    slack = SLACK * (1.0 + abs(log_z_a))
    upper_a = log_z_a + math.log1p(math.exp(margin)) + slack
    rest = -math.expm1(min(log_prior_a, 0.0)) + SLACK  # 1 - P_A, never below its rounding
    if rest <= 0.0 or len(hs.lw) == 0:
        return upper_a
    # c_h: the best over every number of conjuncts from k_h on (suffix maxima of each column).
    suffix = np.maximum.accumulate(lik.bound[::-1], axis=0)[::-1]
    c = suffix[hs.size, np.minimum(n_pos - 1, hs.n_pos)]
    upper_r = math.log(rest) + float(np.logaddexp.reduce(hs.lw + c))
    upper_r += SLACK * (1.0 + abs(upper_r))
    return float(np.logaddexp(upper_a, upper_r))


def listing_work_lower_bound(ss, members, ref, hs, items, lik, threshold, structure_cost,
                             item_cost, stop=np.inf):
    """A lower bound of the listing's work charge, from the first grouping's hypotheses.

    Steps 3 and 4 of the module: over every pair (structure group, subset-pair group), the
    hypotheses at or above ``threshold``, counted from below.

    Parameters
    ----------
    ss : StructureSide
        The first grouping's structure groups (weights relative to ``ref``).
    members : ndarray (G,)
        Structures of each group, in ``ss`` order.
    ref : float
        Log scale of ``ss.weight``.
    hs : SubsetSide
    items : ndarray (H,)
        (global, eventual) subset pairs of each subset-pair group, in ``hs`` order.
    lik : Likelihoods
    threshold : float
        Unnormalised log posterior a counted hypothesis reaches (``log_keep + U``).
    structure_cost, item_cost : float
        The listing's charge per structure of a flagged group and per hypothesis it may list.
    stop : float, default=inf
        Return as soon as the bound passes this (the caller only asks whether it does).

    Returns
    -------
    work : float
        At most the listing's charge.
    n_kept : float
        At most the number of hypotheses at or above ``threshold`` (of the first grouping).
    """
    total = n_kept = 0.0
    with np.errstate(divide="ignore"):
        log_wg = np.log(ss.weight) + ref
    for g in range(len(ss.weight)):
        ll = group_pair_lls(ss, g, hs, lik)
        x = threshold - ll
        x = x + SLACK * (1.0 + np.abs(x))       # a member must beat x by the slack
        b = ss.best[g] + hs.best
        ok = (b >= x) & np.isfinite(ll)
        if not ok.any():
            continue
        # (W - m exp(x)) / exp(b), with W shrunk by the slack; x <= b here: no overflow.
        by_mass = (np.exp(log_wg[g] + hs.lw[ok] - b[ok]) * (1.0 - SLACK)
                   - members[g] * items[ok] * np.exp(x[ok] - b[ok]))
        count = float(np.maximum(by_mass, 1.0).sum())
        n_kept += count
        total += item_cost * count + members[g] * (structure_cost + int(ok.sum()))
        if total * (1.0 - SLACK) > stop:
            break
    return total * (1.0 - SLACK), n_kept * (1.0 - SLACK)
