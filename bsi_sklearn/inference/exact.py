"""Exact posterior by enumeration of the prior's support, over groups of parts.

A hypothesis' likelihood depends only on how many acceptable and unacceptable demonstrations it
satisfies and on its number of conjuncts, so order structures, and pairs of (global subset,
eventual subset), that satisfy the same demonstrations with the same number of conjuncts are
interchangeable: their prior weights are summed into groups and the enumeration runs over pairs
of groups. The order structures are counted, not walked one by one: a dynamic programme over
subsets of subtasks groups them however many there are
(:mod:`bsi_sklearn.inference._structures`); the subsets are grouped in
:mod:`bsi_sklearn.inference._exact_parts`. A first pass computes the normaliser, building per
pair of groups only a histogram over (satisfied positives, satisfied negatives); a second pass
gives every group its posterior mass and flags the structure groups that may hold a hypothesis
above the keep threshold; a walk back down the structure tables splits the masses into clause
marginals and yields the derivations from which the kept hypotheses are listed
(:mod:`bsi_sklearn.inference._structure_walk`, :mod:`bsi_sklearn.inference._listing`).
Structures and pairs of groups that cannot add 1e-17 of the evidence are skipped, with a bound
(:mod:`bsi_sklearn.inference._exact_kernels`). The result is the posterior of the ungrouped
enumeration (:mod:`bsi_sklearn.inference._exact_ungrouped`, the reference it is tested against)
up to rounding. Whether the enumeration runs is decided by a count of its work that depends on
the data only (``max_work``), never by the size of the support.
"""

import math
from typing import NamedTuple

import numpy as np

from bsi_sklearn.inference._budget import (
    SUBSET_BYTES,
    Budget,
    ExactMemoryExceeded,
    ExactWorkExceeded,
    describe_bytes,
    entry_bytes,
)
from bsi_sklearn.inference._exact_kernels import (
    StructureSide,
    SubsetSide,
    group_masses,
    group_pair_lls,
    likelihood_tables,
    log_evidence,
)
from bsi_sklearn.inference._exact_parts import (
    PartTable,
    group_subsets,
    structure_groups,
    subset_items,
    subset_table,
    top_entries,
)
from bsi_sklearn.inference._exact_ungrouped import LabelMasks, ungrouped_kernel
from bsi_sklearn.inference._exact_ungrouped import structure_tables as ungrouped_structures
from bsi_sklearn.inference._grouping import Groups
from bsi_sklearn.inference._listing import Listing, list_hypotheses, members, walk_scratch
from bsi_sklearn.inference._listing_bound import listing_work_lower_bound, log_evidence_upper
from bsi_sklearn.inference._structure_walk import descend
from bsi_sklearn.inference._structures import STEP_COST, StructureTables, structure_tables
from bsi_sklearn.model.bundle import describe_globals
from bsi_sklearn.model.clauses import (
    clause_index_eventual,
    clause_index_order,
    n_clauses,
    pack_rows,
    popcounts,
)
from bsi_sklearn.model.priors import count_model_hypotheses, format_count, support_structures
from bsi_sklearn.model.state_layout import max_conjuncts

__all__ = ["exact_posterior", "exact_refusal", "ExactResult", "ExactWorkExceeded",
           "ExactMemoryExceeded", "MAX_KEPT", "MAX_BYTES"]

#: Default most hypotheses an exact posterior lists (about 100 bytes each).
MAX_KEPT = 1_000_000
#: Default memory limit of the enumeration's tables: every large array is charged against it
#: before it is allocated (:class:`ExactMemoryExceeded`), whatever the work budget.
MAX_BYTES = 4 * 2**30

#: Pairs of groups whose total mass is bounded below exp(_MARGIN) of the evidence are skipped
#: (and never when ``tol`` is 0).
_MARGIN = math.log(1e-17)
_LIST_COST = 4
_EMIT_COST = 4
_KEPT_COST = 16


class ExactResult:
    """What the enumeration returns: kept hypotheses, their log posterior, marginals."""

    def __init__(self, structures, tau_masks, w1_masks, log_prob, dropped_mass,
                 clause_marginals, log_evidence, n_hypotheses, violation_mass, work=None):
        self.structures = structures          # (H, n) parent arrays
        self.tau_masks = tau_masks            # (H, n_g) bool
        self.w1_masks = w1_masks              # (H, n) bool
        self.log_prob = log_prob              # (H,) normalised log posterior, descending
        self.dropped_mass = dropped_mass
        self.clause_marginals = clause_marginals
        self.log_evidence = log_evidence
        self.n_hypotheses = n_hypotheses
        self.violation_mass = violation_mass  # (n_demos + 1,) mass by misclassified demos
        self.work = work                      # the work count spent (None: ungrouped)


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


def _evidence(clause_bits, full, labels, model, thr, cut, hs, lik, margin, budget, walked):
    # Group the structures that satisfy at least thr acceptable demonstrations; log evidence
    # over them (relative to the groups' ref) and what the later passes need. Tables that the
    # last walk goes down again (walked) are charged twice here, so that a budget too small
    # for the walk stops the enumeration while the tables are built, not after every pass.
    n = model.n
    # Before its arrays over the 2**n subsets (about 60 bytes each) are allocated.
    budget.spend(STEP_COST * 8 * 2.0**n, f"the tables of 2**{n} subsets of subtasks")
    budget.allocate(SUBSET_BYTES * 2.0**n, f"the tables of 2**{n} subsets of subtasks")
    times = 2.0 if walked else 1.0
    # The store's entries: held, copied once when the tables are returned, then grouped.
    per_entry = 3 * entry_bytes(clause_bits.shape[1])
    max_entries = budget.entries_left(per_entry)
    tables, work = structure_tables(clause_bits, full, labels.pos, thr, model,
                                    max(budget.left, 0.0) / times, max(max_entries, 0.0))
    if tables is None and budget.left >= times * work:  # stopped by the memory, not the work
        raise ExactMemoryExceeded(
            f"exact enumeration stopped: the order structures' tables over {n} subtasks need "
            f"more than {max(max_entries, 0.0):,.0f} entries ({describe_bytes(per_entry)} "
            f"each), beyond its memory limit of {describe_bytes(budget.max_bytes)}")
    budget.spend(times * work if tables is not None else np.inf,
                 "grouping the order structures" + (" and the walk down them" if walked else ""))
    budget.allocate(per_entry * len(tables.weight), "the order structures' tables")
    sg, members, gid = structure_groups(tables, model)
    budget.spend(len(sg.size) * len(hs.lw),
                 f"{len(sg.size):,} x {len(hs.lw):,} pairs of groups")
    ss, rank = _structure_side(sg, labels.pos)
    found = _Found(tables, sg, members, gid, ss, rank, -np.inf, 0.0)
    if not ss.weight.sum() > 0.0:
        return found
    prior_total = math.log(ss.weight.sum()) + np.logaddexp.reduce(hs.lw)
    log_z_rel = log_evidence(ss, hs, lik, margin - prior_total,
                             cut - sg.ref + margin - prior_total)
    return found._replace(log_z_rel=log_z_rel, offset=margin - prior_total)


class _Found(NamedTuple):
    tables: StructureTables
    sg: Groups           # structure groups, table order
    members: np.ndarray  # structures per group (float)
    gid: np.ndarray      # group of each whole-set entry
    ss: StructureSide    # the groups sorted for the passes
    rank: np.ndarray     # table order -> sorted position
    log_z_rel: float
    offset: float


def _sorted_members(found):
    # The number of structures of each group, in the passes' (StructureSide) order.
    members = np.zeros(len(found.ss.weight))
    members[found.rank] = found.members
    return members


def _listing(found, hs, h_order, subsets, lik, flag, keep, budget):
    # The subset-pair groups each flagged structure group may reach keep with; the work and
    # the number of hypotheses the last walk may list.
    ss, n = found.ss, found.tables.lo.shape[1].bit_length() - 1
    flagged = np.flatnonzero(flag)
    budget.spend(len(flagged) * len(hs.lw), "the pairs of the flagged groups")
    budget.allocate(16.0 * len(flagged) * len(hs.lw), "the pairs of the flagged groups")
    items = subset_items(subsets)[h_order]  # SubsetSide order
    members = _sorted_members(found)
    pass_start = np.zeros(len(ss.weight) + 1, dtype=np.int64)
    pass_h, pass_ll = [], []
    work = n_list = 0.0
    for g in flagged:
        ll = group_pair_lls(ss, g, hs, lik)
        ok = np.flatnonzero(hs.best + ss.best[g] + ll >= keep)
        pass_h.append(ok)
        pass_ll.append(ll[ok])
        pass_start[g + 1] = len(ok)
        n_list += members[g] * items[ok].sum()
        work += members[g] * (_LIST_COST * (n + 1) + len(ok)
                              + (_EMIT_COST + _KEPT_COST) * items[ok].sum())
    budget.spend(work, f"listing the hypotheses of {members[flagged].sum():,.0f} order "
                 "structures")
    pass_h = np.concatenate(pass_h).astype(np.int64) if pass_h else np.empty(0, np.int64)
    pass_ll = np.concatenate(pass_ll) if pass_ll else np.empty(0)
    return np.cumsum(pass_start), pass_h, pass_ll, n_list


def _listing_floor(first, hs, h_order, subsets, lik, n_pos, log_keep, margin, stop=np.inf):
    # A lower bound of _listing's charge from the first grouping, and of the number of
    # hypotheses it lists (_listing_bound; stops once the charge passes stop).
    n = first.tables.lo.shape[1].bit_length() - 1
    upper = log_evidence_upper(first.log_z_rel + first.sg.ref,
                               math.log(first.ss.weight.sum()) + first.sg.ref, hs, lik, n_pos,
                               margin)
    return listing_work_lower_bound(first.ss, _sorted_members(first), first.sg.ref, hs,
                                    subset_items(subsets)[h_order], lik, log_keep + upper,
                                    _LIST_COST * (n + 1), _EMIT_COST + _KEPT_COST, stop=stop)


def _give_up_early(first, hs, h_order, subsets, lik, n_pos, log_keep, margin, budget):
    # Before the second grouping of the structures (most of a failed attempt's time): when
    # the listing's charge is bound to pass what is left of the budget, the attempt would
    # fail there anyway, so it stops now instead.
    if not (budget.left < np.inf and log_keep > -np.inf):
        return
    n = first.tables.lo.shape[1].bit_length() - 1
    items = subset_items(subsets)
    most = first.members.sum() * (_LIST_COST * (n + 1) + len(items)
                                  + (_EMIT_COST + _KEPT_COST) * items.sum())
    if most <= budget.left:  # even listing every hypothesis of the bound's would fit
        return
    work, _ = _listing_floor(first, hs, h_order, subsets, lik, n_pos, log_keep, margin,
                             stop=budget.left)
    if work > budget.left:
        raise ExactWorkExceeded(
            f"exact enumeration stopped: listing the hypotheses would take at least {work:,.0f} "
            "units (a lower bound, before the order structures are grouped), beyond its work "
            "budget")


def _grouped(clause_bits, full, labels, model, log_keep, max_kept, budget, tol):
    subsets = group_subsets(clause_bits, full, model, budget.spend, budget.allocate)
    hs, h_order = _subset_side(subsets.groups, labels)
    max_conj = max_conjuncts(model.n_g, model.n)
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
        # of it: those satisfying at least thr acceptable demonstrations (bound is
        # non-decreasing in them).
        first = _evidence(clause_bits, full, labels, model, n_pos, -np.inf, hs, lik, margin,
                          budget, walked=False)
        if first.log_z_rel > -np.inf:
            cut = first.log_z_rel + first.sg.ref + margin - h_total
            _give_up_early(first, hs, h_order, subsets, lik, n_pos, log_keep, margin, budget)
    thr = int(np.searchsorted(bound, cut)) if cut > -np.inf else 0
    found = _evidence(clause_bits, full, labels, model, thr, cut, hs, lik, margin, budget,
                      walked=True)
    sg, ss = found.sg, found.ss
    log_z = found.log_z_rel + sg.ref
    keep = log_keep + log_z
    budget.spend(len(ss.weight) * len(hs.lw), "the second pass")
    mass_s, mass_h, flag, mass_v = group_masses(ss, hs, lik, found.log_z_rel, keep,
                                                found.log_z_rel + found.offset)
    pass_start, pass_h, pass_ll, n_list = _listing(found, hs, h_order, subsets, lik, flag,
                                                   keep, budget)
    # Down the structure tables: order marginals, and the derivations of the flagged groups.
    ids, lw, _ = top_entries(found.tables, model)
    g_sorted = np.where(found.gid >= 0, found.rank[np.maximum(found.gid, 0)], -1)
    top_out = np.zeros(len(ids))
    held = (g_sorted >= 0) & (mass_s[np.maximum(g_sorted, 0)] > 0)
    top_out[held] = (mass_s[g_sorted[held]] / ss.weight[g_sorted[held]]
                     * np.exp(lw[held] - np.log(found.tables.weight[ids[held]]) - sg.ref))
    marked = (g_sorted >= 0) & (flag[np.maximum(g_sorted, 0)] == 1)
    marg_o, rec_start, rec = descend(found.tables, clause_bits, full, labels.pos, thr, model,
                                     ids, top_out, marked)
    ls = Listing(rec_start, rec, ids[marked].astype(np.int64),
                 g_sorted[marked].astype(np.int64), pass_start, pass_h, pass_ll,
                 h_order.astype(np.int64), keep)
    mass_h = mass_h[np.argsort(h_order)]  # back to the groups' own order
    # Room for every hypothesis that may be listed (n_list bounds them), or the max_kept most
    # probable (a min-heap keeps those).
    room = int(max(1, min(n_list, max_kept)))
    budget.allocate(room * (2.0 * model.n + 24), f"the listing of {room:,} hypotheses")
    par = np.empty((room, model.n), dtype=np.int16 if model.n < 2**15 else np.int64)
    idx, lp = np.empty((room, 2), dtype=np.int64), np.empty(room)
    n_out = min(list_hypotheses(model, hs.best, members(subsets), ls, par, idx, lp,
                                walk_scratch(model.n, room)), room)
    par, idx, lp = par[:n_out], idx[:n_out], lp[:n_out] - log_z
    kept = lp >= log_keep
    par, idx, lp = par[kept].astype(np.int64), idx[kept], lp[kept]
    order = _sorted_head(par, idx[:, 0], idx[:, 1], lp, log_keep > -np.inf, tol)
    marg = np.concatenate([*_subset_marginals(subsets, mass_h, model.n_g, model.n), marg_o])
    return log_z, par[order], idx[order, 0], idx[order, 1], lp[order], marg, mass_v


def _sorted_head(par, t, e, lp, cut, tol):
    # Positions of the listed hypotheses in the result's order (descending posterior; ties by
    # structure, lexicographic parent array, then global and eventual masks), only as far as
    # the shortest prefix covering 1 - tol may reach (with a margin for rounding) when cut.
    head = np.arange(len(lp))
    if cut and len(lp):
        by_lp = np.argsort(-lp, kind="stable")
        cum = np.cumsum(np.exp(lp[by_lp]))
        stop = min(int(np.searchsorted(cum, 1.0 - tol)) + 1, len(lp))
        head = np.flatnonzero(lp >= lp[by_lp[stop - 1]] - 1e-9)
    n = par.shape[1]
    n_g = int(t.max(initial=0)).bit_length()
    if (n + 1) ** n * 2 ** (n_g + n) < 2**62:  # (parent array, t, e) as one number, in order
        key = (par[head] + 1) @ ((n + 1) ** np.arange(n - 1, -1, -1, dtype=np.int64))
        key = (((key << n_g) | t[head]) << n) | e[head]
        return head[np.lexsort((key, -lp[head]))]
    return head[np.lexsort((e[head], t[head], *par[head].T[::-1], -lp[head]))]


def _ungrouped(clause_bits, full, labels, model, log_keep, max_kept, budget, tol):
    n_g, n = model.n_g, model.n
    structures = support_structures(model)
    parts_s = ungrouped_structures(structures, clause_bits, full, model)
    parts_t = PartTable(*subset_table(clause_bits, 0, n_g, model.p_global, full, model.pat_in,
                                      model.pat_out))
    parts_e = PartTable(*subset_table(clause_bits, clause_index_eventual(0, n_g), n,
                                      model.p_eventual, full))
    log_z, keep_idx, keep_lp, mass_s, mass_t, mass_e, mass_v = ungrouped_kernel(
        parts_s, parts_t, parts_e, labels, model, log_keep)
    order = np.argsort(-keep_lp, kind="stable")
    keep_idx, keep_lp = keep_idx[order], keep_lp[order]
    marg = np.zeros(n_clauses(n_g, n))
    t_ids = np.arange(len(mass_t))
    for j in range(n_g):
        marg[j] = mass_t[((t_ids >> j) & 1).astype(bool)].sum()
    e_ids = np.arange(len(mass_e))
    for w in range(n):
        marg[clause_index_eventual(w, n_g)] = mass_e[((e_ids >> w) & 1).astype(bool)].sum()
    for s in np.flatnonzero(mass_s):
        parent = structures[s]
        for v in range(n):
            a = parent[v]
            while a >= 0:
                marg[clause_index_order(a, v, n_g, n)] += mass_s[s]
                a = parent[a]
    return (log_z, structures[keep_idx[:, 0]], keep_idx[:, 1], keep_idx[:, 2], keep_lp, marg,
            mass_v)


def exact_refusal(exc, model, n_hypotheses, prior):
    """The ``ValueError`` of ``inference="exact"`` stopped by ``exc`` (its memory limit).

    It names the template's size, the table that did not fit and the way out.
    """
    return ValueError(
        f"inference='exact' cannot enumerate this posterior ({describe_globals(model)}, "
        f"{model.n} subtasks, {format_count(n_hypotheses)} hypotheses, prior={prior!r}): "
        f"{exc}. Use inference='auto' or 'mcmc', or restrict the roles (global_candidates=, "
        "subtasks=) to fewer propositions")


def exact_posterior(truth, y01, model, tol=1e-9, grouped=True, max_kept=MAX_KEPT,
                    max_work=None, max_bytes=MAX_BYTES):
    """Enumerate the support and return the posterior.

    Parameters
    ----------
    truth : ndarray (n_demos, n_clauses) uint8
        Clause truth matrix (:func:`bsi_sklearn.model.clauses.clause_truth`).
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
        Work budget, in evaluations of a pair of groups (about 5-10 ns each here; a
        combination of two entries of the structure tables counts 4, a new entry 32, a
        (global, eventual) subset pair that may be listed 20): :class:`ExactWorkExceeded` is
        raised as soon as the enumeration is known to need more, before that work is done or
        its memory allocated. The count depends on the data only, never on the support's
        size or on timing, so the outcome is the same on every machine. ``None``: no limit.
        The ungrouped reference ignores it.
    max_bytes : float or None, default=MAX_BYTES
        Memory limit of the enumeration's large arrays (the tables over subsets of subtasks
        and of candidates, the order structures' store, the pairs of groups, the listing):
        each is charged before it is allocated and :class:`ExactMemoryExceeded` raised
        instead, also without a work budget. ``None``: no limit. The ungrouped reference
        ignores it.

    Raises
    ------
    ExactWorkExceeded
        When ``max_work`` is exceeded.
    ExactMemoryExceeded
        (a subclass of ``ExactWorkExceeded``) when ``max_bytes`` would be exceeded.

    Returns
    -------
    ExactResult
        ``violation_mass[v]``: the posterior mass of the hypotheses that misclassify ``v``
        demonstrations (violated acceptable plus satisfied unacceptable ones), over the whole
        support. The kept hypotheses are every hypothesis of normalised log posterior at least
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
    n_hyp = count_model_hypotheses(model)
    log_keep = math.log(tol) - math.log(n_hyp) if tol > 0 else -np.inf  # n_hyp may pass 1e308
    engine = _grouped if grouped else _ungrouped
    budget = Budget(max_work, max_bytes)
    log_z, structures, t_masks, e_masks, keep_lp, marg, mass_v = engine(
        clause_bits, full, labels, model, log_keep, max_kept, budget, tol)
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
        violation_mass=mass_v,
        work=budget.spent if grouped else None,
    )
