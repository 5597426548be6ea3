"""Convergence diagnostics: split-R-hat, missed mass, total variation, warning thresholds."""

import math

import numpy as np

__all__ = ["split_rhat", "missed_mass", "total_variation", "disagreement_problems",
           "RHAT_WARN", "MISSED_WARN", "MODE_WARN"]

#: Split-R-hat of the chains' log posteriors above which the chains have not mixed.
RHAT_WARN = 1.05
#: A chain that never reached more than this much of the posterior mass the chains found
#: (neither visited it nor led to it from a visited state through weighed neighbours):
#: chains disagree.
MISSED_WARN = 0.05
#: A deterministic optimum more probable than every visited state by more than this factor
#: (log 20): the chains sit on a wrong mode, however well they agree.
MODE_WARN = math.log(20.0)


def split_rhat(traces):
    """Split-R-hat (Gelman et al., BDA3) of a scalar across chains.

    Computed on the traces less their overall mean, so that log posteriors with a large
    offset lose no precision. Differences at the rounding level of the traces (1e-9 of their
    magnitude: the sampler tracks log posteriors incrementally) are no signal: chains that are
    each constant at that level give 1.0 when they agree and ``inf`` when they sit on
    different values, never a huge finite ratio of rounding noise.

    Parameters
    ----------
    traces : ndarray of shape (n_chains, n_draws)

    Returns
    -------
    float
        1.0 when every draw is identical (a chain that never moves off a sharp mode); ``inf``
        when chains sit on different constant values or a trace is not finite; ``nan`` with
        fewer than 4 draws.

    Examples
    --------
    >>> import numpy as np
    >>> split_rhat(np.zeros((2, 10)))
    1.0
    >>> split_rhat(np.array([[0.0] * 10, [1.0] * 10]))
    inf
    >>> split_rhat(1e12 + np.array([[0.0, 1.0] * 5, [1.0, 0.0] * 5]))
    1.0
    """
    traces = np.asarray(traces, dtype=float)
    n_draws = traces.shape[1]
    half = n_draws // 2
    if half < 2:
        return float("nan")
    split = np.concatenate([traces[:, :half], traces[:, half:2 * half]], axis=0)
    if not np.isfinite(split).all():
        return float("inf")
    noise = 1e-9 * max(1.0, float(np.abs(split).max()))
    split = split - split.mean()
    means = split.mean(axis=1)
    within = split.var(axis=1, ddof=1).mean()
    if math.sqrt(within) <= noise:
        return 1.0 if np.ptp(means) <= noise else float("inf")
    between = half * means.var(ddof=1)
    var_plus = (half - 1) / half * within + between / half
    return float(np.sqrt(var_plus / within))


def missed_mass(chain_visits, probabilities):
    """Posterior mass outside each chain's states.

    The reported MCMC posterior is the exact posterior restricted to the states all chains
    visited; a chain's own posterior is the same restricted to the states it found. The total
    variation between the two is the reported mass outside the chain's set, which this
    returns per chain. Chains that each found the states carrying the mass give ~0, however
    their raw log-posterior traces wander; a chain stuck away from mass the others found gives
    that mass. The sampler passes each chain's *reached* states
    (:func:`bsi_sklearn.inference._reach.reach`: visited, or one Gibbs block from a visited
    one, so weighed exactly by the chain's updates): on a plateau of equally probable states
    a chain weighs nearly all of them long before it has visited each.

    Parameters
    ----------
    chain_visits : sequence of array-like of int
        For each chain, the indices (into ``probabilities``) of the states it visited;
        repeats allowed.
    probabilities : ndarray of shape (n_states,)
        The reported probabilities of the posterior's states.

    Returns
    -------
    missed : ndarray of shape (n_chains,)
        ``1 - (mass of the states the chain visited)``, in [0, 1].

    Examples
    --------
    >>> import numpy as np
    >>> probs = np.array([0.7, 0.2, 0.1])
    >>> missed_mass([[0, 1], [0, 1, 2, 0]], probs).round(3).tolist()
    [0.1, 0.0]
    """
    probabilities = np.asarray(probabilities, dtype=float)
    out = np.empty(len(chain_visits))
    for c, visits in enumerate(chain_visits):
        seen = np.zeros(len(probabilities), dtype=bool)
        seen[np.asarray(visits, dtype=np.int64)] = True
        out[c] = min(1.0, max(0.0, 1.0 - math.fsum(probabilities[seen])))
    return out


def total_variation(p, q):
    """Total-variation distance between two posteriors (over specifications).

    Parameters
    ----------
    p, q : Posterior or mapping Specification -> probability

    Examples
    --------
    >>> from bsi_sklearn import Specification
    >>> a, b = Specification(globals=[0]), Specification()
    >>> total_variation({a: 0.5, b: 0.5}, {a: 1.0})
    0.5
    """
    def as_dict(d):
        if hasattr(d, "specifications") and hasattr(d, "probabilities"):
            return dict(zip(d.specifications, d.probabilities))
        return dict(d)

    p, q = as_dict(p), as_dict(q)
    keys = set(p) | set(q)
    return 0.5 * math.fsum(abs(p.get(k, 0.0) - q.get(k, 0.0)) for k in keys)


def disagreement_problems(diag):
    """What a sampler's diagnostics say is wrong, one sentence each (empty when nothing is).

    A better optimum than the chains found (``optimum_gap > MODE_WARN``), a chain that missed
    more than ``MISSED_WARN`` of the mass the chains found, a split-R-hat above
    ``RHAT_WARN`` (NaN, too few samples, says nothing): the estimator warns with each.
    """
    problems = []
    if diag["optimum_gap"] > MODE_WARN:
        problems.append(
            "MCMC chains missed a mode: a deterministic search found a specification "
            f"exp({diag['optimum_gap']:.3g}) times more probable than any state the chains "
            "recorded (mcmc_diagnostics_['optimum_gap'] > log 20); it is in the reported "
            "posterior, but the chains did not sample its neighbourhood, so the rest of "
            "the reported posterior is unreliable.")
    worst = diag["max_missed_mass"]
    if worst > MISSED_WARN:
        chain = int(np.argmax(diag["missed_mass_per_chain"]))
        problems.append(
            f"MCMC chains disagree: chain {chain} never reached specifications holding "
            f"{worst:.1%} of the mass the chains found (> {MISSED_WARN:.0%}; "
            "mcmc_diagnostics_['missed_mass_per_chain']: neither visited them nor led to "
            "them from a state it visited through weighed neighbours), so the reported "
            "posterior is unreliable.")
    if diag["rhat"] > RHAT_WARN:  # nan (too few samples) does not warn
        problems.append(
            f"MCMC chains have not mixed: the split-R-hat of their log posteriors is "
            f"{diag['rhat']:.3g} (> {RHAT_WARN}; mcmc_diagnostics_['rhat']).")
    return problems
