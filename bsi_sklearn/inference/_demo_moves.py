"""Moves of many clauses at once, each about one demonstration: where the beam search stops short.

Under the size principle (CB, the paper's likelihood) a clause earns ``log 2`` for every acceptable
demonstration the formula satisfies, and a misclassified demonstration costs ``|log eps|``,
thousands of nats with hundreds of candidate clauses (``log eps`` grows with them). So the
formula either keeps an acceptable demonstration, and every clause it violates is out, or gives
it up, and every clause that only it violated is in: one clause at a time, each step of either
change is worse than the last. The beam search (one block a step) stops on the wrong side:
on a Declare log of 40 activities with pattern clauses (issue 28), its optimum gave up two
acceptable demonstrations for 31 clauses and lay 6,213 nats below what the chains found after
thousands of sweeps.

:func:`demo_moves` lists, from one hypothesis, the two moves per demonstration:

- *keep* a misclassified acceptable demonstration: drop every global and eventual clause it
  violates, and cut every order it violates (its later subtask leaves its parent: a set of
  chains or a forest stays one; under Prior 1, one chain through every subtask, a
  demonstration that violates an order is not kept);
- *give up* a satisfied acceptable demonstration: add every global and eventual clause that
  it alone of the satisfied acceptable ones violates.

:func:`best_demo_move` scores them exactly, and pairs of them where no single one improves;
the caller continues the beam search from the best where it beats the hypothesis
(:func:`bsi_sklearn.inference.mcmc.deterministic_optimum`). No random numbers.
"""

import numpy as np

from bsi_sklearn.inference._chain_kernel import score_rows
from bsi_sklearn.model.clauses import clause_index_eventual, clause_index_order
from bsi_sklearn.model.priors import structures_are_sets
from bsi_sklearn.model.state_layout import split_state

__all__ = ["demo_moves", "best_demo_move"]

#: Candidate clauses whose violations are read at once (a block of them times the rows).
SLOT_BLOCK = 1024


def demo_moves(row, demos, model):
    """The keep and give-up moves of every acceptable demonstration, from ``row``.

    Parameters
    ----------
    row : ndarray of int
        A hypothesis ``[tau, w1, parent]`` (:mod:`bsi_sklearn.model.state_layout`).
    demos : Demos
        Deduplicated clause truth (:func:`bsi_sklearn.inference.mcmc.deduplicate_demos`).
    model : Model

    Returns
    -------
    ndarray of shape (n_moves, len(row)), int64
        One hypothesis per move that changes ``row``: the keep moves of the misclassified
        acceptable rows, then the give-up moves, each in the order of the deduplicated rows.

    Examples
    --------
    Two global candidates, no subtasks, three acceptable demonstrations: the second violates
    ``G(1)`` alone, the third ``G(0)`` alone. From ``G(0)``, keeping the third drops it, and
    giving up the second adds ``G(1)``; from the formula without clauses, giving up either
    adds the clause it alone violates.

    >>> import numpy as np
    >>> from bsi_sklearn.inference.mcmc import deduplicate_demos
    >>> from bsi_sklearn.model.bundle import make_model
    >>> truth = np.array([[1, 1], [1, 0], [0, 1]], dtype=np.uint8)  # columns: G(0), G(1)
    >>> demos = deduplicate_demos(truth, np.array([1, 1, 1]))
    >>> model = make_model(prior="sets_of_chains", likelihood="cb", n_globals=2, n_subtasks=0)
    >>> demo_moves(np.array([1, 0]), demos, model).tolist()
    [[0, 0], [1, 1]]
    >>> demo_moves(np.array([0, 0]), demos, model).tolist()
    [[1, 0], [0, 1]]
    """
    n_g, n = model.n_g, model.n
    row = np.asarray(row, dtype=np.int64)
    tau, w1, parent = split_state(row, n_g, n)
    eventual = np.array([clause_index_eventual(w, n_g) for w in range(n)], dtype=np.int64)
    free_at = np.r_[np.flatnonzero(tau), n_g + np.flatnonzero(w1)]  # positions in the row
    free = np.r_[np.flatnonzero(tau), eventual[np.flatnonzero(w1)]].astype(np.int64)
    pairs = [(a, b) for b in range(n) for a in _ancestors(parent, b)]
    orders = np.array([clause_index_order(a, b, n_g, n) for a, b in pairs], dtype=np.int64)
    truth = demos.truth_t
    held = np.r_[free, orders].astype(np.int64)
    sat = (np.logical_and.reduce(truth[held] != 0, axis=0) if len(held)
           else np.ones(truth.shape[1], dtype=bool))
    pos = demos.w_pos > 0
    moves = []
    cut = structures_are_sets(model)
    later = np.array([b for _, b in pairs], dtype=np.int64)  # each order's later subtask
    rejected = np.flatnonzero(pos & ~sat)
    free_kept = truth[np.ix_(free, rejected)] != 0  # (clauses x rejected rows)
    orders_kept = truth[np.ix_(orders, rejected)] != 0
    for k in range(len(rejected)):
        broken = later[~orders_kept[:, k]]
        if len(broken) and not cut:
            continue
        out = row.copy()
        out[free_at[~free_kept[:, k]]] = 0
        out[n_g + n + broken] = -1
        moves.append(out)
    # Give up: the clauses outside the row that exactly one satisfied acceptable row violates.
    held_free = np.zeros(n_g + n, dtype=bool)
    held_free[free_at] = True
    out_at = np.flatnonzero(~held_free)
    out_slot = np.r_[np.arange(n_g), eventual][out_at]
    kept_rows = np.flatnonzero(pos & sat)
    by_row = {}
    for lo in range(0, len(out_at) if len(kept_rows) else 0, SLOT_BLOCK):
        # A block of clauses at a time: (clauses x rows) booleans of SLOT_BLOCK rows at most.
        violated = truth[np.ix_(out_slot[lo:lo + SLOT_BLOCK], kept_rows)] == 0
        for i in np.flatnonzero(violated.sum(axis=1) == 1):
            by_row.setdefault(int(kept_rows[np.argmax(violated[i])]), []).append(out_at[lo + i])
    for d in sorted(by_row):
        out = row.copy()
        out[np.array(by_row[d], dtype=np.int64)] = 1
        moves.append(out)
    return np.array(moves, dtype=np.int64).reshape(len(moves), len(row))


def best_demo_move(row, lp, demos, model, width):
    """The best of the moves about one demonstration from ``row``, or of pairs of them.

    Pairs are tried only where no single move beats ``lp`` (the log posterior of ``row``):
    from each of the ``width`` best single moves, its own best move (keeping one rejected case
    while giving up another takes two: 948 nats on a Declare log of 40 activities).

    Returns
    -------
    move : ndarray of int64 or None
        ``None`` where there is no move.
    log_posterior : float
        Its exact log posterior (``-inf`` without a move); not necessarily above ``lp``.
    """
    moves = demo_moves(row, demos, model)
    if not len(moves):
        return None, -np.inf
    lps = _scores(moves, demos, model)
    best = int(np.argmax(lps))
    move, move_lp = moves[best], float(lps[best])
    if move_lp > lp:
        return move, move_lp
    for i in np.argsort(-lps, kind="stable")[:width]:
        second = demo_moves(moves[i], demos, model)
        if len(second):
            second_lps = _scores(second, demos, model)
            k = int(np.argmax(second_lps))
            if second_lps[k] > move_lp:
                move, move_lp = second[k], float(second_lps[k])
    return move, move_lp


def _scores(rows, demos, model):
    # Scored as the sampler's int16 states: the kernel's one specialisation, which the compile
    # step builds (int64 rows compiled another at a fit's first demonstration move, 1.4 s).
    return score_rows(np.ascontiguousarray(rows, dtype=np.int16), demos, model)


def _ancestors(parent, b):
    a = parent[b]
    while a >= 0:
        yield int(a)
        a = parent[a]
