"""One-block moves of a hypothesis: enumerated as four numbers, written out, scored exactly.

A neighbour of a hypothesis changes one block of the Gibbs sampler: one global bit, or one
subtask's place in the order structure together with its eventual bit (one eventual bit when
there is no order to change). A move is kept as four numbers (:data:`N_MOVE`), so that a
search over many neighbours writes out only the rows it keeps. Each move is scored from the
row's own violation counts, to the bit what scoring its row from scratch gives
(:func:`bsi_sklearn.inference._local_search._score`; tested):

- a bit flip (:func:`score_flip`) from the rows violating nothing or only its clause, as
  bitsets, and the parts of the log prior the flip leaves as they are;
- a subtask's places (:func:`score_moved`) from the rows that violate nothing once the
  subtask's own clauses are out (:func:`prepare_moves`, once per subtask), as bitsets ANDed
  with the clauses each place adds back.

The satisfied counts are whole numbers, so the bitsets' weighted popcounts equal the row by row
sums, and the log prior's terms are summed in :func:`bsi_sklearn.model.priors.log_prior`'s
order.
"""

from typing import NamedTuple

import numpy as np

from bsi_sklearn._jit import helper
from bsi_sklearn.inference._gibbs_moves import add_pair
from bsi_sklearn.inference._row_counts import (
    flip_masks,
    mask_sums,
    weighted_popcount,
    zero_mask,
)
from bsi_sklearn.model.clauses import clause_index_eventual, clause_index_order
from bsi_sklearn.model.likelihood import log_likelihood
from bsi_sklearn.model.priors import (
    is_forest,
    log_prior,
    log_prior_structure,
    log_prior_subset,
)
from bsi_sklearn.model.state_layout import parent_offset, split_state, state_width, w1_offset

__all__ = ["N_MOVE", "FlipScratch", "MoveScratch", "flip_scratch", "move_scratch",
           "prepare_flips", "score_flip", "detach", "place", "enumerate_moves", "write_move",
           "neighbours", "prepare_moves", "score_moved", "n_flip_bits", "put_row", "put_move",
           "n_neighbours_max"]


class FlipScratch(NamedTuple):
    masks: np.ndarray   # (2, W) uint64: flip_masks of the loaded row's counts
    prefix: np.ndarray  # (n_pat + 1,): log_prior_globals' running sum over the loaded row
    parts: np.ndarray   # (4,): its W1 and structure terms; its G terms, one G clause more / less


def flip_scratch(demos, model):
    return FlipScratch(np.zeros((2, demos.bits.shape[1]), dtype=np.uint64),
                       np.zeros(model.pat_in.shape[0] + 1), np.zeros(4))


@helper
def patterns_from(lp, tau, start, model):
    # log_prior_globals' sum of the pattern clauses' terms from `start` on, added to lp.
    n_gp = model.n_g - model.pat_in.shape[0]
    for i in range(start, model.pat_in.shape[0]):
        lp += model.pat_in[i] if tau[n_gp + i] else model.pat_out[i]
    return lp


@helper
def prepare_flips(viol, model, scratch, flips):
    # For the bit flips of the row loaded in `scratch` (_load), with violation counts `viol`:
    # the rows violating nothing / only one clause (the likelihood's counts), and the parts of
    # log_prior a flip leaves as they are, so that its prior is log_prior's sum in its order.
    flip_masks(viol, flips.masks)
    tau, prefix, parts = scratch.tau, flips.prefix, flips.parts
    n_gp = model.n_g - model.pat_in.shape[0]
    k = 0
    for j in range(n_gp):
        k += tau[j]
    prefix[0] = log_prior_subset(k, n_gp, model.p_global)
    for i in range(model.pat_in.shape[0]):
        prefix[i + 1] = prefix[i] + (model.pat_in[i] if tau[n_gp + i] else model.pat_out[i])
    parts[0] = log_prior_subset(scratch.w1.sum(), model.n, model.p_eventual)
    parts[1] = log_prior_structure(scratch.parent, model)
    parts[2] = patterns_from(log_prior_subset(k + 1, n_gp, model.p_global), tau, 0, model)
    parts[3] = patterns_from(log_prior_subset(k - 1, n_gp, model.p_global), tau, 0, model)


@helper
def score_flip(b, n_conj, demos, model, scratch, flips):
    # _score of the row loaded in `scratch` (_load, prepare_flips) with inclusion bit b
    # flipped, `n_conj` its conjuncts: the same number, bit for bit (log_prior's terms summed
    # in its order, the unchanged ones kept from the row; the satisfied counts are whole
    # numbers, equal as bitset popcounts), the row never copied.
    n_g = model.n_g
    n_gp = n_g - model.pat_in.shape[0]
    if b < n_g:
        inc = scratch.tau[b]
        if b < n_gp:  # a G clause: the subset term with one more or one fewer
            g = flips.parts[3] if inc else flips.parts[2]
        else:  # a pattern clause: its term changed, the ones after it summed again
            i = b - n_gp
            g = patterns_from(flips.prefix[i] + (model.pat_out[i] if inc else model.pat_in[i]),
                              scratch.tau, i + 1, model)
        lp = g + flips.parts[0] + flips.parts[1]
        c = b
    else:  # an eventual bit (no orders): log_prior over the arrays, the bit flipped and back
        w = b - n_g
        inc = scratch.w1[w]
        scratch.w1[w] = 1 - inc
        lp = log_prior(scratch.tau, scratch.w1, scratch.parent, model)
        scratch.w1[w] = inc
        c = clause_index_eventual(w, n_g)
    if lp == -np.inf:
        return lp
    ps_out, ns_out, ps_in, ns_in = mask_sums(flips.masks, c, inc, demos)
    if inc:
        return lp + log_likelihood(ps_out, ns_out, demos.n_pos, demos.n_neg, n_conj - 1,
                                   model.log_eps, model.likelihood, model.flips)
    return lp + log_likelihood(ps_in, ns_in, demos.n_pos, demos.n_neg, n_conj + 1,
                               model.log_eps, model.likelihood, model.flips)


class MoveScratch(NamedTuple):
    viol: np.ndarray   # (D,) int32: the row's counts without the moved subtask's clauses
    zrest: np.ndarray  # (1, W) uint64: the rows violating none of those clauses
    mask: np.ndarray   # (1, W) uint64: a candidate's rows
    work: np.ndarray   # (3, n) int64: detach's structure without v, successors, moved set


def move_scratch(demos, model):
    n_words = demos.bits.shape[1]
    return MoveScratch(np.zeros(demos.truth_t.shape[1], dtype=np.int32),
                       np.zeros((1, n_words), dtype=np.uint64),
                       np.zeros((1, n_words), dtype=np.uint64),
                       np.zeros((3, model.n), dtype=np.int64))


# A move is four numbers (b, v, u, g): b >= 0 flips inclusion bit b; otherwise subtask v
# leaves its place (detach) and is put back under / after u (-1: a root, a new chain) with
# eventual bit g & 1, or (g & 2, chains) at the head of u's chain; (-1, -1, 0, 0) is the row
# itself. The beam search keeps moves, not rows: a row is written out only when kept.
N_MOVE = 4


@helper
def detach(row, v, model, work):
    # Subtask v's place removed from the row's structure, into work[0]: v's children hang from
    # its parent (chains) or stay in its subtree (forests, which move the whole subtree).
    # work[1]: the successors in that structure; work[2]: the set that moves (v; v's subtree).
    n_g, n = model.n_g, model.n
    base = parent_offset(n_g, n)
    rest, child, in_s = work[0], work[1], work[2]
    for u in range(n):
        rest[u] = row[base + u]
        in_s[u] = 0
    if is_forest(model):
        for u in range(n):
            a = u
            while a >= 0 and a != v:
                a = rest[a]
            in_s[u] = 1 if a == v else 0
    else:
        in_s[v] = 1
        for u in range(n):
            if rest[u] == v:
                rest[u] = rest[v]
    rest[v] = -1
    for u in range(n):
        child[u] = -1
    for u in range(n):
        if rest[u] >= 0:
            child[rest[u]] = u


@helper
def place(v, u, g, model, work, parent):
    # The structure of move (., v, u, g) into `parent`, from detach(row, v)'s work.
    rest, child = work[0], work[1]
    for w in range(model.n):
        parent[w] = rest[w]
    if g & 2:  # v at the head of u's chain
        parent[u] = v
    else:
        parent[v] = u
        if u >= 0 and not is_forest(model) and child[u] >= 0:
            parent[child[u]] = v


@helper
def put_move(moves, k, b, v, u, g):
    moves[k, 0] = b
    moves[k, 1] = v
    moves[k, 2] = u
    moves[k, 3] = g


@helper
def enumerate_moves(row, model, moves, k, work):
    # Every move one block away from ``row``, into moves[k:]; returns the new k. The inclusion
    # bits first (tau's, and W1's too when there is no order to move them with), then every
    # subtask's places: as a root / new chain, under (forests) or after (chains) any node
    # outside what moves, and (chains) at the head of any chain; each with F(v) out and in.
    n = model.n
    for j in range(n_flip_bits(model)):
        put_move(moves, k, j, -1, 0, 0)
        k += 1
    if n <= 1:
        return k
    rest, in_s = work[0], work[2]
    for v in range(n):
        detach(row, v, model, work)
        for u in range(-1, n):
            if u >= 0 and in_s[u]:
                continue
            for f in range(2):
                put_move(moves, k, -1, v, u, f)
                k += 1
            if u >= 0 and not is_forest(model) and rest[u] < 0:
                for f in range(2):
                    put_move(moves, k, -1, v, u, f | 2)
                    k += 1
    return k


@helper
def write_move(row, move, model, out, i, work):
    # The row `move` makes of `row`, into out[i].
    n_g, n = model.n_g, model.n
    n_cols = state_width(n_g, n)
    put_row(out, i, row, n_cols)
    b, v = move[0], move[1]
    if b >= 0:
        out[i, b] = 1 - row[b]
    elif v >= 0:
        detach(row, v, model, work)
        out[i, w1_offset(n_g) + v] = move[3] & 1
        base = parent_offset(n_g, n)
        place(v, move[2], move[3], model, work, out[i, base:])


@helper
def neighbours(row, model, out, k, work, moves):
    # Every row one block away from ``row``, into out[k:] (its moves into moves[k:]); returns
    # the new k. work: (3, n) int64 scratch.
    k_end = enumerate_moves(row, model, moves, k, work)
    for i in range(k, k_end):
        write_move(row, moves[i], model, out, i, work)
    return k_end


@helper
def cross_pairs(parent, in_s, take_out, viol, mask, demos, model):
    # The order clauses of `parent` between the moved set and the rest (an ancestor on one
    # side, its descendant on the other): taken out of `viol` (take_out), or ANDed into
    # `mask`. Returns their number.
    n_g, n = model.n_g, model.n
    count = 0
    for y in range(n):
        a = parent[y]
        while a >= 0:
            if in_s[a] != in_s[y]:
                c = clause_index_order(a, y, n_g, n)
                if take_out:
                    add_pair(viol, demos.truth_t, c, np.int64(-1))
                else:
                    for w in range(mask.shape[1]):
                        mask[0, w] &= demos.bits[c, w]
                count += 1
            a = parent[a]
    return count


@helper
def prepare_moves(row, v, viol, n_conj, demos, model, moves):
    # For the structure moves of subtask v of `row` (violation counts `viol`, `n_conj`
    # conjuncts): its place detached (moves.work), and the rows that violate nothing once v's
    # eventual clause and the orders across the moved set are out (a move only adds such
    # clauses back; every other clause of the row stays). Returns the conjuncts left and the
    # four prior terms a chain move can have (score_moved's): its W1 term with F(v) out and
    # in, its structure term with v in a chain of the others and as a chain of its own.
    n_g, n = model.n_g, model.n
    detach(row, v, model, moves.work)
    rest = moves.viol
    for d in range(rest.shape[0]):
        rest[d] = viol[d]
    if row[w1_offset(n_g) + v]:
        add_pair(rest, demos.truth_t, clause_index_eventual(v, n_g), np.int64(-1))
        n_conj -= 1
    _, row_w1, parent = split_state(row, n_g, n)
    n_conj -= cross_pairs(parent, moves.work[2], True, rest, moves.mask, demos, model)
    zero_mask(rest, moves.zrest)
    k_rest = 0
    m_rest = 0
    for w in range(n):
        if w != v:
            k_rest += row_w1[w]
            if moves.work[0, w] < 0:
                m_rest += 1
    return (n_conj, log_prior_subset(k_rest, n, model.p_eventual),
            log_prior_subset(k_rest + 1, n, model.p_eventual),
            model.lp_chains[m_rest], model.lp_chains[m_rest + 1])


@helper
def score_moved(row, move, lp_g, rest, demos, model, scratch, moves):
    # _score of the row structure move `move` makes of `row`, prepared by prepare_moves
    # (`rest`: what it returns; the row's global clauses' log prior `lp_g`): the same
    # number, bit for bit (log_prior's sum in its order; the satisfied counts are whole
    # numbers, equal as bitset popcounts), in O(orders across the move x words) instead of
    # O(D x conjuncts), the row never written out. Chains in O(that) alone: the prior from
    # the counts, the orders across the move walked from v; forests (a subtree moves) in O(n).
    if not is_forest(model):
        return _score_chain_move(move, lp_g, rest, demos, model, moves)
    n_conj_rest = rest[0]
    n_g, n = model.n_g, model.n
    w1, parent, mask = scratch.w1, scratch.parent, moves.mask
    v, g = move[1], move[3]
    _, row_w1, _ = split_state(row, n_g, n)
    for w in range(n):
        w1[w] = row_w1[w]
    w1[v] = g & 1
    place(v, move[2], g, model, moves.work, parent)
    lp = (lp_g + log_prior_subset(w1.sum(), w1.shape[0], model.p_eventual)
          + log_prior_structure(parent, model))
    if lp == -np.inf:
        return lp
    for w in range(mask.shape[1]):
        mask[0, w] = moves.zrest[0, w]
    n_conj = n_conj_rest
    if w1[v]:
        _and_clause(mask, demos, clause_index_eventual(v, n_g))
        n_conj += 1
    n_conj += cross_pairs(parent, moves.work[2], False, moves.viol, mask, demos, model)
    return _masked_score(mask, lp, n_conj, demos, model)


@helper
def _score_chain_move(move, lp_g, terms, demos, model, moves):
    # score_moved for chains: v put after u (or at the head of u's chain, or as a chain of
    # its own) in detach's structure (moves.work). Its prior from prepare_moves' terms (F(v)
    # in or out; the model's table by number of chains, one more only as a chain of its own,
    # the values log_prior_structure gives, bit for bit: tested); the orders across the move
    # are v's new ancestors (u and up) and descendants (u's old successor, or u itself at the
    # head, and down): the pairs cross_pairs finds, in another order (AND and counts commute).
    n_g, n = model.n_g, model.n
    rest, succ, mask = moves.work[0], moves.work[1], moves.mask
    v, u, g = move[1], move[2], move[3]
    head = (g & 2) != 0
    lp = (lp_g + (terms[2] if g & 1 else terms[1])) + (terms[4] if u < 0 else terms[3])
    if lp == -np.inf:
        return lp
    for w in range(mask.shape[1]):
        mask[0, w] = moves.zrest[0, w]
    n_conj = terms[0]
    if g & 1:
        _and_clause(mask, demos, clause_index_eventual(v, n_g))
        n_conj += 1
    a = -1 if head else u
    while a >= 0:
        _and_clause(mask, demos, clause_index_order(a, v, n_g, n))
        n_conj += 1
        a = rest[a]
    d = u if head else (succ[u] if u >= 0 else -1)
    while d >= 0:
        _and_clause(mask, demos, clause_index_order(v, d, n_g, n))
        n_conj += 1
        d = succ[d]
    return _masked_score(mask, lp, n_conj, demos, model)


@helper
def _and_clause(mask, demos, c):
    # The rows of `mask` that also satisfy clause c.
    for w in range(mask.shape[1]):
        mask[0, w] &= demos.bits[c, w]


@helper
def _masked_score(mask, lp, n_conj, demos, model):
    # lp plus the log-likelihood of a formula of n_conj conjuncts satisfied by the rows of mask.
    ps = 0
    ns = 0
    for w in range(mask.shape[1]):
        word = mask[0, w]
        if word != 0:
            ps += weighted_popcount(word, demos.pos_planes, w)
            ns += weighted_popcount(word, demos.neg_planes, w)
    return lp + log_likelihood(float(ps), float(ns), demos.n_pos, demos.n_neg, n_conj,
                               model.log_eps, model.likelihood, model.flips)


@helper
def n_flip_bits(model):
    # The inclusion bits neighbours flips first: tau's, and W1's when there is no order.
    return parent_offset(model.n_g, model.n) if model.n <= 1 else w1_offset(model.n_g)


@helper
def put_row(out, k, row, n_cols):
    for c in range(n_cols):
        out[k, c] = row[c]


def n_neighbours_max(n_g, n):
    """The most neighbours one hypothesis has (rows of the buffer of ``neighbours``)."""
    return n_g + n + n * 2 * (2 * n + 1)
