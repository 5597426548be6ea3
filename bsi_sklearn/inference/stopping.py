"""When the sampler's chains may stop: ``n_samples="auto"``.

The reported MCMC posterior is the exact posterior restricted to the states the chains found
(:mod:`bsi_sklearn.inference.mcmc`), so more sweeps help only by finding states that carry
mass. With ``n_samples="auto"`` the chains run in rounds that double the sweeps recorded
(``FIRST_ROUND``, twice that, ... up to ``MAX_SAMPLES``), and stop after a round where

- no chain missed more than ``STOP_MISSED`` of the mass they found together
  (:func:`bsi_sklearn.inference.diagnostics.missed_mass`): they agree;
- the split-R-hat of their log posteriors is at most ``STOP_RHAT``;
- the states first found in the round's second half (by any chain) hold at most
  ``STOP_LATE`` of that mass: the chains have stopped finding what matters.

A chain's share is what it *reached* (:mod:`bsi_sklearn.inference._reach`): visited, or one
Gibbs block from a visited state, whose weight the chain's update computed exactly and drew
against; on a plateau of equally probable states (interchangeable subtasks of an event log's
order structure) each chain reaches nearly all of it long before it has visited every state.
Where the closure below is computed, a chain's share is what its own visited states lead to
through it, among everything found.
A state is *found* when it is visited, or one block from a found state that is visited or
nearly as probable as the best (:mod:`bsi_sklearn.inference._closure`, which weighs them, and
whose states the sampler reports), so the late mass counts the first sweep at which a state
was found. Counting reach without reporting the reached states would hide the mass still being
found (a walk's new state is always one block from its last; on a diffuse CI posterior of 4,672
states it stopped after one round at TV 0.013 to exact); with them reported, the diffuse CI
posteriors of the tests stop after the first round at TV 0.0002 or less, where counting visits
ran up to 10,000 sweeps for TV 0.0002-0.0009. Past the closure's work budget the late mass counts
first visits.

Past the closure's budget a second rule may stop the chains: a posterior whose support is too
large to list (a diffuse one: the calibrated likelihood's on an event log, where every formula
consistent with the labels ties and a thousand weakly determined clauses combine) keeps giving
the late mass that the first rule waits to fall, round after round, and the reported posterior,
restricted to the states found, can never be complete however long the chains run. There the
chains stop when they agree on what the sampler reports of it: every clause's posterior
inclusion, under each chain's share, within ``STOP_INCLUSION`` of the pooled posterior's, and
the split-R-hat at most ``STOP_RHAT``. Measured on a 40-activity, 1,000-case log under the
calibrated likelihood (``benchmarks/RESULTS_default_candidates.md``): the first rule's late mass
was 0.30 after 500 sweeps and still 0.16 after 10,000, the chains' largest inclusion gap 0.005
after 500; the held-out predictions of 500 and 10,000 sweeps score alike.

A posterior too diffuse to list at all (its visited states, reweighted exactly, far above the
chains' own log posterior: :func:`bsi_sklearn.inference.diagnostics.typical_gap`) is reported
by the chains' samples, and they stop when they agree on what the samples report: the
split-R-hat of every clause's inclusion, and of their log posteriors, at most ``STOP_RHAT``.

Every quantity is exact-scored, and the rules depend on the chains only, never on timing or
on ``n_jobs``. A peaked posterior stops after the first round; a flat one, where the chains
keep finding states and disagree, runs to ``MAX_SAMPLES`` as a fixed ``n_samples`` would.
"""

import numpy as np

from bsi_sklearn.inference.diagnostics import missed_mass, split_rhat, weighted_inclusion

__all__ = ["FIRST_ROUND", "MAX_SAMPLES", "STOP_MISSED", "STOP_RHAT", "STOP_LATE",
           "STOP_INCLUSION", "rounds", "should_stop", "inclusion_by_chain"]

#: Sweeps recorded per chain by the first round of ``n_samples="auto"``.
FIRST_ROUND = 500
#: The most sweeps recorded per chain (the paper's number of samples).
MAX_SAMPLES = 10_000
#: Stop thresholds: a tenth of the warning's missed mass, a fifth of its R-hat excess.
STOP_MISSED = 0.005
STOP_RHAT = 1.01
STOP_LATE = 0.001
#: Past the closure's budget: the largest gap between a chain's and the pooled inclusion of a
#: clause at which the chains may stop (a vote moved by a hundredth at most per clause).
STOP_INCLUSION = 0.01


def rounds(first=FIRST_ROUND, most=MAX_SAMPLES):
    """Cumulative sweeps recorded per chain after each round: doubling, capped at ``most``.

    Examples
    --------
    >>> rounds()
    [500, 1000, 2000, 4000, 8000, 10000]
    """
    out = [min(first, most)]
    while out[-1] < most:
        out.append(min(2 * out[-1], most))
    return out


def should_stop(shares, probabilities, first_found, traces, inclusion=None, sampled=None):
    """Whether the chains may stop after this round, and the quantities it weighs.

    Parameters
    ----------
    shares : sequence of ndarray of int
        For each chain, the index (into ``probabilities``) of every state in its share: what
        its visited states lead to (:mod:`bsi_sklearn.inference._closure`), or what it
        reached (:func:`bsi_sklearn.inference._reach.reach`), or what it visited.
    probabilities : ndarray of shape (n_states,)
        The exact posterior restricted to the states found (or visited), normalised.
    first_found : ndarray of shape (n_states,)
        The first recorded sweep (of any chain) at which each state was found (or visited).
    traces : ndarray of shape (n_chains, n_recorded)
        The chains' log posteriors after every recorded sweep.
    inclusion : ndarray of shape (1 + n_chains, n_slots), optional
        Past the closure's budget only (:func:`inclusion_by_chain`): each clause's inclusion
        under the pooled posterior (row 0) and under each chain's share.
    sampled : float, optional
        For a posterior too diffuse to list, reported by its samples only: the largest
        split-R-hat of a clause's inclusion across the chains
        (:func:`~bsi_sklearn.inference.diagnostics.inclusion_rhat`). The chains then stop
        when it and the R-hat of their log posteriors are at most ``STOP_RHAT``; ``shares``,
        ``probabilities`` and ``first_found`` are not read.

    Returns
    -------
    stop : bool
    detail : dict
        ``max_missed_mass``, ``rhat``, ``late_mass``; with ``inclusion``, also
        ``max_inclusion_gap``; with ``sampled``, ``rhat`` and ``inclusion_rhat`` only.

    Examples
    --------
    >>> import numpy as np
    >>> probs = np.array([0.9995, 0.0005])
    >>> stop, detail = should_stop([np.array([0, 1]), np.array([0])], probs,
    ...                            np.array([0, 7]), np.zeros((2, 10)))
    >>> stop, detail["late_mass"]
    (True, 0.0005)
    """
    rhat = split_rhat(traces)
    if sampled is not None:
        return (bool(rhat <= STOP_RHAT and sampled <= STOP_RHAT),
                {"rhat": rhat, "inclusion_rhat": sampled})
    missed = float(missed_mass(shares, probabilities).max())
    half = traces.shape[1] // 2
    late = float(np.sum(probabilities[first_found >= half]))
    stop = missed <= STOP_MISSED and rhat <= STOP_RHAT and late <= STOP_LATE
    detail = {"max_missed_mass": missed, "rhat": rhat, "late_mass": late}
    if inclusion is not None:
        gap = float(np.abs(inclusion[1:] - inclusion[0]).max(initial=0.0))
        detail["max_inclusion_gap"] = gap
        stop = stop or (gap <= STOP_INCLUSION and rhat <= STOP_RHAT)
    return stop, detail


def inclusion_by_chain(states, probabilities, shares, n_g, n):
    """Each clause's posterior inclusion: pooled (row 0), and under each chain's share.

    Parameters
    ----------
    states : ndarray of shape (n_states, n_g + 2 n)
        State rows (:mod:`bsi_sklearn.model.state_layout`).
    probabilities : ndarray of shape (n_states,)
        Their posterior, normalised.
    shares : sequence of ndarray of int
        For each chain, the indices of the states in its share, whose posterior restricted to
        them (renormalised) is the chain's own; a share without mass gives a row of zeros.
    n_g, n : int
        Global slots and subtasks.

    Returns
    -------
    ndarray of shape (1 + n_chains, n_slots)
        Slot ``c`` in the layout of :mod:`bsi_sklearn.model.clauses` (unused slots 0).

    Examples
    --------
    >>> import numpy as np
    >>> states = np.array([[1, 1, -1], [0, 1, -1]])  # G(0) & F(0), and F(0): n_g = 1, n = 1
    >>> inclusion_by_chain(states, np.array([0.75, 0.25]), [np.array([0]), np.array([1])],
    ...                    1, 1)[:, :2].tolist()
    [[0.75, 1.0], [1.0, 1.0], [0.0, 1.0]]
    """
    weights = np.zeros((1 + len(shares), len(probabilities)))
    weights[0] = probabilities
    for k, share in enumerate(shares):
        mass = probabilities[share].sum()
        if mass > 0:
            weights[1 + k, share] = probabilities[share] / mass
    return weighted_inclusion(states, weights, n_g, n)
