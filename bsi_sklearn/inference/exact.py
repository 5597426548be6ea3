"""Exact posterior by enumeration of the prior's support, over groups of parts.

A hypothesis' likelihood depends only on how many acceptable and unacceptable demonstrations it
satisfies and on its number of conjuncts, so order structures, and pairs of (global subset,
eventual subset), that satisfy the same demonstrations with the same number of conjuncts are
interchangeable: their prior weights are summed into groups
(:mod:`bsi_sklearn.inference._exact_parts`) and the enumeration runs over pairs of groups. A
first pass computes the normaliser, building per pair of groups only a histogram over
(satisfied positives, satisfied negatives); a second pass gives every group its posterior mass
and flags the structure groups that may hold a hypothesis above the keep threshold; a last walk
over the order structures splits the masses into clause marginals and lists the kept
hypotheses. Order structures and pairs of groups that cannot add 1e-17 of the evidence are
skipped, with a bound (:mod:`bsi_sklearn.inference._exact_kernels`). The result is the
posterior of the ungrouped enumeration (:mod:`bsi_sklearn.inference._exact_ungrouped`, the
reference it is tested against) up to rounding.
"""

import math

import numpy as np

from bsi_sklearn.clauses import pack_rows, popcounts
from bsi_sklearn.inference._exact_kernels import (
    Expansion,
    StructureSide,
    SubsetSide,
    group_masses,
    likelihood_tables,
    log_evidence,
    walk_structures,
)
from bsi_sklearn.inference._exact_parts import (
    PartTable,
    Pruning,
    group_structures,
    group_subsets,
    subset_table,
)
from bsi_sklearn.inference._exact_ungrouped import LabelMasks, structure_tables, ungrouped_kernel
from bsi_sklearn.priors import PRIORS, count_hypotheses, support_structures

__all__ = ["exact_posterior", "ExactResult", "ExactWorkExceeded", "MAX_KEPT"]

#: Default most hypotheses an exact posterior lists (about 100 bytes each).
MAX_KEPT = 1_000_000

#: Pairs of groups whose total mass is bounded below exp(_MARGIN) of the evidence are skipped
#: (and never when ``tol`` is 0).
_MARGIN = math.log(1e-17)
_STRUCTURE_COST = 100
_EMIT_COST = 20


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


def _subset_marginals(subsets, mass_h, n_g, n):
    # Each subset-pair group's mass goes to its pairs of groups in proportion to their prior
    # weight, then to the members of each global / eventual group in proportion to theirs.
    g = subsets.groups
    with np.errstate(divide="ignore"):
        h_lw = np.log(g.weight) + g.ref
    of_pair = np.repeat(np.arange(len(mass_h)), np.diff(subsets.pair_start))
    held = mass_h[of_pair] > 0  # (a group without mass may have weight 0: no 0 * inf)
    pair_mass = np.zeros(len(of_pair))
    pair_mass[held] = mass_h[of_pair][held] * np.exp(subsets.pair_lw[held]
                                                     - h_lw[of_pair][held])
    out = []
    for part, group_of_pair, start, items, item_lp, n_items in (
            (subsets.t_groups, subsets.pair_t, subsets.t_start, subsets.t_items, subsets.t_lp,
             n_g),
            (subsets.e_groups, subsets.pair_e, subsets.e_start, subsets.e_items, subsets.e_lp,
             n)):
        mass_part = np.bincount(group_of_pair, weights=pair_mass, minlength=len(part.size))
        marg = np.zeros(n_items)
        for gp in np.flatnonzero(mass_part):
            members = items[start[gp]:start[gp + 1]]
            share = mass_part[gp] * np.exp(item_lp[members] - part.ref) / part.weight[gp]
            marg += (_mask_bits(members, n_items) * share[:, None]).sum(axis=0)
        out.append(marg)
    return out


def _structure_side(sg, pos):
    # Sorted by size class, then by decreasing satisfied positives (the passes' early exits).
    n_pos = popcounts(sg.bits, pos)
    order = np.lexsort((-n_pos, sg.size))
    rank = np.empty(len(order), dtype=np.int64)
    rank[order] = np.arange(len(order))
    size = sg.size[order]
    cls_size, cls_first = np.unique(size, return_index=True)
    side = StructureSide(np.ascontiguousarray(sg.bits[order]), sg.weight[order], sg.best[order],
                         n_pos[order], size, np.append(cls_first, len(size)).astype(np.int64),
                         cls_size.astype(np.int64))
    return side, rank


def _subset_side(hg, labels):
    with np.errstate(divide="ignore"):
        lw = np.log(hg.weight) + hg.ref
    pos = np.ascontiguousarray(hg.bits & labels.pos)
    n_pos = popcounts(pos, labels.pos)
    order = np.argsort(-n_pos, kind="stable")
    side = SubsetSide(np.ascontiguousarray(pos[order]),
                      np.ascontiguousarray((hg.bits & labels.neg)[order]), hg.size[order],
                      lw[order], hg.best[order], n_pos[order])
    return side, order


class ExactWorkExceeded(RuntimeError):
    """The enumeration would take more work than the budget it was given (``max_work``)."""


class _Budget:
    # Work in units of one pair-of-groups evaluation (about 5-10 ns here): a structure walked
    # costs about _STRUCTURE_COST of them, a hypothesis the last walk may list (every subset
    # pair of a structure whose group may hold a kept hypothesis) about _EMIT_COST. The count
    # depends on the data only, never on timing.
    def __init__(self, max_work):
        self.left = np.inf if max_work is None else float(max_work)

    def visits(self):
        return int(min(self.left / _STRUCTURE_COST, 2**62))

    def spend(self, work, what):
        self.left -= work
        if self.left < 0:
            raise ExactWorkExceeded(f"exact enumeration stopped: {what} exceeds its work budget")


def _evidence(full, model, rule, hs, lik, margin, budget):
    # Group the structures the rule keeps; log evidence over them (relative to the groups'
    # ref) and what the later passes need.
    table, sg, members, n_visited, complete = group_structures(full, model, rule)
    budget.spend(_STRUCTURE_COST * n_visited, f"walking {n_visited:,} order structures")
    if not complete:
        budget.spend(np.inf, "walking the order structures")
    budget.spend(len(sg.size) * len(hs.lw),
                 f"{len(sg.size):,} x {len(hs.lw):,} pairs of groups")
    ss, rank = _structure_side(sg, rule.pos)
    if not ss.weight.sum() > 0.0:
        return table, sg, ss, rank, members, -np.inf, 0.0
    prior_total = math.log(ss.weight.sum()) + np.logaddexp.reduce(hs.lw)
    log_z_rel = log_evidence(ss, hs, lik, margin - prior_total,
                             rule.cut - sg.ref + margin - prior_total)
    return table, sg, ss, rank, members, log_z_rel, margin - prior_total


def _grouped(clause_bits, full, labels, model, log_keep, max_kept, max_work):
    budget = _Budget(max_work)
    subsets = group_subsets(clause_bits, full, model)
    hs, h_order = _subset_side(subsets.groups, labels)
    max_conj = model.n_g + model.n + model.n * (model.n - 1) // 2
    lik = likelihood_tables(int(labels.n_pos), int(labels.n_neg), max_conj, model)
    # What is skipped holds at most exp(margin) of the evidence, and no kept hypothesis.
    margin = min(_MARGIN, log_keep)
    bound = lik.bound.max(axis=0)  # over every number of conjuncts
    n_pos = int(labels.n_pos)
    h_total = float(np.logaddexp.reduce(hs.lw))
    cut = -np.inf
    if margin > -np.inf and n_pos > 0:
        # A lower bound of the evidence from the structures whose orders every acceptable
        # demonstration satisfies; then every structure that could add more than exp(margin)
        # of it.
        rule = Pruning(clause_bits, labels.pos, bound, -np.inf, n_pos, budget.visits())
        _, sg1, _, _, _, log_z1, _ = _evidence(full, model, rule, hs, lik, margin, budget)
        if log_z1 > -np.inf:
            cut = log_z1 + sg1.ref + margin - h_total
    rule = Pruning(clause_bits, labels.pos, bound, cut, 0, budget.visits())
    table, sg, ss, rank, members, log_z_rel, offset = _evidence(full, model, rule, hs, lik,
                                                                margin, budget)
    log_z = log_z_rel + sg.ref
    keep = log_keep + log_z
    cut_pairs = log_z_rel + offset
    budget.spend(len(ss.weight) * len(hs.lw), "the second pass")
    mass_s, mass_h, flag = group_masses(ss, hs, lik, log_z_rel, keep, cut_pairs)
    n_expand = int(members[flag.astype(bool)[rank]].sum())  # members: table order
    n_subsets = 2 ** (model.n_g + model.n)
    budget.spend(_EMIT_COST * n_expand * n_subsets + _STRUCTURE_COST * int(members.sum()),
                 f"listing the hypotheses of {n_expand:,} order structures")
    ex = Expansion(rank, mass_s, sg.ref, flag, h_order, keep)
    mass_h = mass_h[np.argsort(h_order)]  # back to the groups' own order
    room = max(1, min(n_expand * n_subsets, max_kept))  # at most what may be listed
    while True:
        par = np.empty((room, model.n), dtype=np.int64)
        idx, lp = np.empty((room, 3), dtype=np.int64), np.empty(room)
        marg_o, n_out = walk_structures(full, model, rule, table, ss, hs, lik, ex, subsets, par,
                                        idx, lp)
        if n_out <= room or room == max_kept:
            break
        room = min(n_out, max_kept)  # rare: walk again with room for more
    n_out = min(n_out, room)
    par, idx, lp = par[:n_out], idx[:n_out], lp[:n_out] - log_z
    kept = lp >= log_keep
    par, idx, lp = par[kept], idx[kept], lp[kept]
    order = np.lexsort((idx[:, 2], idx[:, 1], idx[:, 0], -lp))
    marg = np.concatenate([*_subset_marginals(subsets, mass_h, model.n_g, model.n), marg_o])
    return log_z, par[order], idx[order, 1], idx[order, 2], lp[order], marg


def _ungrouped(clause_bits, full, labels, model, log_keep, max_kept, max_work):
    n_g, n = model.n_g, model.n
    structures = support_structures(model)
    parts_s = structure_tables(structures, clause_bits, full, model)
    parts_t = PartTable(*subset_table(clause_bits, 0, n_g, model.p_global, full))
    parts_e = PartTable(*subset_table(clause_bits, n_g, n, model.p_eventual, full))
    log_z, keep_idx, keep_lp, mass_s, mass_t, mass_e = ungrouped_kernel(
        parts_s, parts_t, parts_e, labels, model, log_keep)
    order = np.argsort(-keep_lp, kind="stable")
    keep_idx, keep_lp = keep_idx[order], keep_lp[order]
    marg = np.zeros(n_g + n + n * n)
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
    return (log_z, structures[keep_idx[:, 0]], keep_idx[:, 1], keep_idx[:, 2], keep_lp, marg)


def exact_posterior(truth, y01, model, tol=1e-9, grouped=True, max_kept=MAX_KEPT,
                    max_work=None):
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
    grouped : bool, default=True
        Enumerate groups of interchangeable parts (the engine); ``False`` runs the ungrouped
        reference over every hypothesis.
    max_kept : int, default=MAX_KEPT
        Most hypotheses returned (bounds the memory of a nearly flat posterior); when more are
        needed to cover ``1 - tol`` the most probable are kept and ``dropped_mass`` says how
        much the rest hold. The clause marginals and the evidence are exact either way. The
        ungrouped reference ignores it.
    max_work : float or None, default=None
        Work budget, in evaluations of a pair of groups (about 5-10 ns each here; a structure
        walked counts 100, a hypothesis that may be listed 20): :class:`ExactWorkExceeded` is
        raised as soon as the enumeration is
        known to need more. The count depends on the data only, so the outcome is the same on
        every machine. ``None``: no limit. The ungrouped reference ignores it.

    Raises
    ------
    ExactWorkExceeded
        When ``max_work`` is exceeded.

    Returns
    -------
    ExactResult
        The kept hypotheses are every hypothesis of normalised log posterior at least
        ``log(tol / n_hypotheses)``, cut to the shortest most-probable prefix that covers
        ``1 - tol``; ties are ordered by structure (lexicographic parent array), then global
        and eventual subset masks.
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
    n_hyp = count_hypotheses(PRIORS[model.prior], n_g, n)
    log_keep = math.log(tol / n_hyp) if tol > 0 else -np.inf
    engine = _grouped if grouped else _ungrouped
    log_z, structures, t_masks, e_masks, keep_lp, marg = engine(clause_bits, full, labels,
                                                                model, log_keep, max_kept,
                                                                max_work)
    # Smallest prefix of the sorted kept hypotheses that covers 1 - tol.
    cum = np.cumsum(np.exp(keep_lp))
    if tol > 0:
        stop = int(np.searchsorted(cum, 1.0 - tol)) + 1
        structures, t_masks, e_masks = structures[:stop], t_masks[:stop], e_masks[:stop]
        keep_lp, cum = keep_lp[:stop], cum[:stop]
    dropped = max(0.0, 1.0 - float(cum[-1])) if len(cum) else 1.0
    return ExactResult(
        structures=structures,
        tau_masks=_mask_bits(t_masks, n_g),
        w1_masks=_mask_bits(e_masks, n),
        log_prob=keep_lp,
        dropped_mass=dropped,
        clause_marginals=marg,
        log_evidence=log_z,
        n_hypotheses=n_hyp,
    )
