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

Every quantity is exact-scored, and the rule depends on the chains only, never on timing or
on ``n_jobs``. A peaked posterior stops after the first round; a flat one, where the chains
keep finding states, runs to ``MAX_SAMPLES`` as a fixed ``n_samples`` would.
"""

import numpy as np

from bsi_sklearn.inference.diagnostics import missed_mass, split_rhat

__all__ = ["FIRST_ROUND", "MAX_SAMPLES", "STOP_MISSED", "STOP_RHAT", "STOP_LATE", "rounds",
           "should_stop"]

#: Sweeps recorded per chain by the first round of ``n_samples="auto"``.
FIRST_ROUND = 500
#: The most sweeps recorded per chain (the paper's number of samples).
MAX_SAMPLES = 10_000
#: Stop thresholds: a tenth of the warning's missed mass, a fifth of its R-hat excess.
STOP_MISSED = 0.005
STOP_RHAT = 1.01
STOP_LATE = 0.001


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


def should_stop(shares, probabilities, first_found, traces):
    """Whether the chains may stop after this round, and the three quantities it weighs.

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

    Returns
    -------
    stop : bool
    detail : dict
        ``max_missed_mass``, ``rhat``, ``late_mass``.

    Examples
    --------
    >>> import numpy as np
    >>> probs = np.array([0.9995, 0.0005])
    >>> stop, detail = should_stop([np.array([0, 1]), np.array([0])], probs,
    ...                            np.array([0, 7]), np.zeros((2, 10)))
    >>> stop, detail["late_mass"]
    (True, 0.0005)
    """
    missed = float(missed_mass(shares, probabilities).max())
    rhat = split_rhat(traces)
    half = traces.shape[1] // 2
    late = float(np.sum(probabilities[first_found >= half]))
    stop = missed <= STOP_MISSED and rhat <= STOP_RHAT and late <= STOP_LATE
    return stop, {"max_missed_mass": missed, "rhat": rhat, "late_mass": late}
