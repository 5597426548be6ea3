"""Convergence diagnostics: split-R-hat, missed mass, total variation, warning thresholds."""

import math

import numpy as np

from bsi_sklearn.model.clauses import clause_masks, clause_sums, n_clauses
from bsi_sklearn.model.state_layout import split_states

__all__ = ["split_rhat", "missed_mass", "typical_gap", "unseen_mass", "too_diffuse",
           "weighted_inclusion", "half_inclusions", "inclusion_rhat", "listing_gap",
           "total_variation", "disagreement_problems", "RHAT_WARN", "MISSED_WARN", "MODE_WARN",
           "DIFFUSE_GAP", "LISTING_TOL", "LISTING_Z"]

#: Split-R-hat of the chains' log posteriors above which the chains have not mixed.
RHAT_WARN = 1.05
#: A chain that never reached more than this much of the posterior mass the chains found
#: (neither visited it nor led to it from a visited state through weighed neighbours):
#: chains disagree.
MISSED_WARN = 0.05
#: A deterministic optimum more probable than every visited state by more than this factor
#: (log 20): the chains sit on a wrong mode, however well they agree.
MODE_WARN = math.log(20.0)
#: A posterior whose visited states, reweighted exactly, lie this far (log 20) above the
#: chains' own log posterior on average is too diffuse to list (:func:`typical_gap`).
DIFFUSE_GAP = math.log(20.0)
#: A listed posterior whose inclusion of a clause lies more than ``LISTING_TOL`` (a vote moved by
#: a hundredth) and more than ``LISTING_Z`` standard errors from the chains' samples' does not
#: report what they sample (:func:`listing_gap`).
LISTING_TOL = 0.01
LISTING_Z = 4.0
#: States whose clause bitsets :func:`weighted_inclusion` holds at once (200 propositions'
#: 40,000 clause slots: 20 MB).
INCLUSION_BLOCK = 4096


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
    return float(_rhat(means, within, half))


def _rhat(means, within, half):
    # Split-R-hat (BDA3) from the halves' means (axis 0) and their mean within-half variance.
    between = half * np.var(means, axis=0, ddof=1)
    var_plus = (half - 1) / half * within + between / half
    return np.sqrt(var_plus / within)


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


def typical_gap(scores, counts, traces):
    """How far the chains' states lie below the visited states reweighted exactly.

    The mean log posterior of the visited states under the exact posterior restricted to them,
    less the chains' mean log posterior. Where the chains sample a posterior whose visited
    states hold its mass, the two are the same average and the gap is near 0. Where its mass
    is spread over far more states than the chains can visit twice (many clauses the data
    leave undetermined, each near its prior inclusion), the restricted posterior piles onto
    the few most probable states visited, far above the chains' typical ones: the gap is
    large, and the restricted posterior is not the posterior. Chains stuck away from a better
    mode give no gap (their visited states are what they sample); that is ``optimum_gap``.
    Chains stuck in different modes do (the best one's states outweigh the others'): so a
    posterior is too diffuse to list only where the samples also say that much of its mass
    lies in states not seen (:func:`too_diffuse`).

    Parameters
    ----------
    scores : ndarray of shape (n_states,)
        Exact unnormalised log posterior of each state.
    counts : ndarray of shape (n_states,)
        Samples of each state (0: not visited).
    traces : ndarray of shape (n_chains, n_samples)
        The chains' log posteriors after every recorded sweep.

    Returns
    -------
    float
        In nats; 0.0 without samples.

    Examples
    --------
    Samples in proportion to the exact posterior: no gap.

    >>> import numpy as np
    >>> scores, counts = np.log([0.6, 0.3, 0.1]), np.array([6, 3, 1])
    >>> traces = np.repeat(scores, counts)[None, :]
    >>> round(typical_gap(scores, counts, traces), 12)
    0.0

    A thousand states, each visited once, ten of them 10 nats above the rest:

    >>> scores = np.r_[np.full(10, 10.0), np.zeros(990)]
    >>> round(typical_gap(scores, np.ones(1000), scores[None, :]), 2)
    9.9
    """
    scores, counts = np.asarray(scores, dtype=float), np.asarray(counts)
    if np.size(traces) == 0 or not (counts > 0).any():
        return 0.0
    visited = scores[counts > 0]
    weights = np.exp(visited - visited.max())
    return float(weights @ visited / weights.sum() - np.mean(traces))


def unseen_mass(counts):
    """The Good-Turing estimate of the posterior mass in states the chains never visited.

    The share of the samples whose state was sampled exactly once (Good 1953): near 0 where
    the chains return to the states they sample, near 1 where nearly every sample is a new
    state. The chains' autocorrelation makes it low, if anything (a state visited for two
    sweeps in a row is not a singleton).

    Parameters
    ----------
    counts : ndarray of shape (n_states,)
        Samples of each state (0: not visited).

    Returns
    -------
    float
        0.0 without samples.

    Examples
    --------
    >>> import numpy as np
    >>> unseen_mass(np.array([6, 3, 1, 0]))
    0.1
    """
    counts = np.asarray(counts)
    total = int(counts.sum())
    return float(np.count_nonzero(counts == 1) / total) if total else 0.0


def too_diffuse(scores, counts, traces):
    """Whether a posterior is too diffuse to list, with the two quantities that say so.

    Too diffuse where the visited states, reweighted exactly, lie more than ``DIFFUSE_GAP``
    above the chains' states (:func:`typical_gap`) and the samples put more than
    ``MISSED_WARN`` of the mass in states never visited (:func:`unseen_mass`): a large gap
    with few unseen states is chains stuck in different modes, a disagreement to warn of.

    Returns
    -------
    diffuse : bool
    gap, unseen : float
    """
    gap, unseen = typical_gap(scores, counts, traces), unseen_mass(counts)
    return _diffuse(gap, unseen), gap, unseen


def _diffuse(gap, unseen):
    # too_diffuse's rule, on its two quantities (also as mcmc_diagnostics_ records them).
    return bool(gap > DIFFUSE_GAP and unseen > MISSED_WARN)


def weighted_inclusion(states, weights, n_g, n):
    """Each clause's inclusion under each row of weights over the states.

    Parameters
    ----------
    states : ndarray of shape (n_states, n_g + 2 n)
        State rows (:mod:`bsi_sklearn.model.state_layout`).
    weights : ndarray of shape (n_rows, n_states)
        For example probabilities, one distribution a row.
    n_g, n : int
        Global slots and subtasks.

    Returns
    -------
    ndarray of shape (n_rows, n_slots)
        ``out[k, c]``: the weight of row ``k`` on the states holding clause slot ``c`` (the
        layout of :mod:`bsi_sklearn.model.clauses`; unused slots 0).

    Examples
    --------
    >>> import numpy as np
    >>> states = np.array([[1, 1, -1], [0, 1, -1]])  # G(0) & F(0), and F(0): n_g = 1, n = 1
    >>> weighted_inclusion(states, np.array([[0.75, 0.25]]), 1, 1)[:, :2].tolist()
    [[0.75, 1.0]]
    """
    weights = np.asarray(weights, dtype=float)
    tau, w1, parent = split_states(np.asarray(states), n_g, n)
    out = np.zeros((len(weights), 64 * ((n_clauses(n_g, n) + 63) // 64)))
    # The states' clause bitsets a block at a time: at most INCLUSION_BLOCK rows of them.
    for lo in range(0, weights.shape[1], INCLUSION_BLOCK):
        hi = lo + INCLUSION_BLOCK
        masks = clause_masks(np.ascontiguousarray(parent[lo:hi], dtype=np.int64),
                             np.ascontiguousarray(tau[lo:hi], dtype=np.bool_),
                             np.ascontiguousarray(w1[lo:hi], dtype=np.bool_), n_g, n)
        out += clause_sums(masks, np.ascontiguousarray(weights[:, lo:hi]))
    return out


def inclusion_rhat(states, chain_rows, chain_counts, n_g, n):
    """The largest split-R-hat of a clause's inclusion across the chains.

    Each clause's indicator (the recorded state holds it) is a scalar of every sample, whose
    split-R-hat compares the chains' halves (Vehtari et al. 2021 recommend it for indicator
    functions): near 1 when every half includes the clause about as often as the others,
    given how much it varies within them, so it allows for the chains' autocorrelation. Where
    the posterior is reported by its samples, this is how the chains are asked whether they
    agree. A clause every half includes always, or never, gives 1 (``inf`` if the halves differ).

    Parameters
    ----------
    states : ndarray of shape (n_states, n_g + 2 n)
        The visited states' rows.
    chain_rows, chain_counts : sequence of ndarray of int
        For each chain, the index into ``states`` of each row of its run-length encoded record,
        and the samples the row stands for.
    n_g, n : int

    Returns
    -------
    float
        ``nan`` with fewer than 4 samples a chain.

    Examples
    --------
    Two chains, each alternating between a state with ``G(0)`` and one without, five
    samples at a time: they agree. Two that each stay in one: they do not.

    >>> import numpy as np
    >>> states = np.array([[0], [1]])  # without G(0), with it: n_g = 1, n = 0
    >>> rows, counts = [np.array([0, 1, 0, 1])] * 2, [np.array([5, 5, 5, 5])] * 2
    >>> bool(inclusion_rhat(states, rows, counts, 1, 0) < 1.01)
    True
    >>> inclusion_rhat(states, [np.array([0]), np.array([1])], [np.array([20])] * 2, 1, 0)
    inf
    """
    halves = half_inclusions(states, chain_rows, chain_counts, n_g, n)
    if halves is None:
        return float("nan")
    means, half = halves
    # A binary indicator's variance within a half is its mean times one less it (ddof=1).
    within = np.mean(means * (1.0 - means), axis=0) * half / (half - 1)
    noise = 1e-12
    flat = within <= noise
    if np.any(flat & (np.ptp(means, axis=0) > noise)):
        return float("inf")
    return float(_rhat(means[:, ~flat], within[~flat], half).max(initial=1.0))


def half_inclusions(states, chain_rows, chain_counts, n_g, n):
    """Each clause's inclusion in each half of each chain's samples.

    Parameters are :func:`inclusion_rhat`'s.

    Returns
    -------
    means : ndarray of shape (2 n_chains, n_clauses)
        Row ``2 k`` the first half of chain ``k``'s samples, row ``2 k + 1`` the second (the
        halves as long as the shortest chain's, a run across the middle split).
    half : int
        Samples in each half.

    ``None`` with fewer than 4 samples a chain.
    """
    half = min(int(np.sum(c)) for c in chain_counts) // 2
    if half < 2:
        return None
    weights = np.zeros((2 * len(chain_rows), len(states)))
    for k, (rows, counts) in enumerate(zip(chain_rows, chain_counts)):
        counts = np.asarray(counts, dtype=np.int64)
        start = np.cumsum(counts) - counts
        early = np.clip(half - start, 0, counts)  # a run across the middle is split
        late = np.clip(2 * half - start, 0, counts) - early
        np.add.at(weights[2 * k], rows, early / half)
        np.add.at(weights[2 * k + 1], rows, late / half)
    return weighted_inclusion(states, weights, n_g, n)[:, :n_clauses(n_g, n)], half


def listing_gap(listed, halves):
    """How far a listed posterior's clause inclusions lie from its chains' samples'.

    Where the chains sample the posterior, the share of their samples holding a clause
    estimates its inclusion without bias, whatever the states never visited; the listed
    posterior (the exact one restricted to the states found) is biased where the states not
    found hold mass unevenly across clauses: a flat posterior of half a million
    specifications, whose many-clause states are too many to find, listed with each clause's
    inclusion up to 0.08 off while the samples were within 0.01. A gap counts where it is
    more than ``LISTING_Z`` standard errors of the samples' estimate (the spread of the
    chains' halves' inclusions, :func:`half_inclusions`, which allows for their
    autocorrelation); the listing does not report the posterior where a counted gap exceeds
    ``LISTING_TOL``.

    Parameters
    ----------
    listed : ndarray of shape (n_clauses,)
        Each clause's inclusion under the listed posterior.
    halves : ndarray of shape (n_halves, n_clauses)
        Each clause's inclusion in each chain half's samples.

    Returns
    -------
    float
        The largest counted gap; 0.0 where none is beyond the samples' noise.

    Examples
    --------
    Four halves that include a clause about half the time, a listing that says 0.505 (within
    their noise), and one that says 0.7:

    >>> import numpy as np
    >>> halves = np.array([[0.49], [0.51], [0.50], [0.50]])
    >>> listing_gap(np.array([0.505]), halves), round(listing_gap(np.array([0.7]), halves), 6)
    (0.0, 0.2)
    """
    halves = np.asarray(halves, dtype=float)
    pooled = halves.mean(axis=0)
    error = halves.std(axis=0, ddof=1) / math.sqrt(len(halves))
    gap = np.abs(np.asarray(listed, dtype=float) - pooled)
    return float(gap[gap > LISTING_Z * error].max(initial=0.0))


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

    A posterior too diffuse to list (:func:`too_diffuse`: ``typical_gap > DIFFUSE_GAP`` and
    ``unseen_mass > MISSED_WARN``) is
    reported by its samples (:func:`bsi_sklearn.inference.mcmc.sample_posterior`): the
    optimum gap and the missed mass, which weigh states by their exact posterior, say
    nothing there (the chains leave the optimum they start from and never meet); there the
    chains are asked whether each clause's inclusion agrees across them
    (``inclusion_rhat > RHAT_WARN``, :func:`inclusion_rhat`) besides the R-hat of their log
    posteriors. So is a posterior whose restriction to the states found fails the missed
    mass's check while the chains agree on every inclusion (``sampled`` with a lower
    ``typical_gap``): its optimum gap still warns.

    Examples
    --------
    >>> diag = {"optimum_gap": 26.4, "max_missed_mass": 0.9, "missed_mass_per_chain": [0.9],
    ...         "rhat": 1.0, "typical_gap": 30.0, "sampled": True, "inclusion_rhat": 1.002}
    >>> disagreement_problems(diag)
    []
    """
    problems = []
    diffuse = _diffuse(diag.get("typical_gap", 0.0), diag.get("unseen_mass", 1.0))
    listed = not diag.get("sampled", diffuse)
    if not diffuse and diag["optimum_gap"] > MODE_WARN:
        problems.append(
            "MCMC chains missed a mode: a deterministic search found a specification "
            f"exp({diag['optimum_gap']:.3g}) times more probable than any state the chains "
            "recorded (mcmc_diagnostics_['optimum_gap'] > log 20); it is in the reported "
            "posterior, but the chains did not sample its neighbourhood, so the rest of "
            "the reported posterior is unreliable.")
    worst = diag["max_missed_mass"]
    if listed and worst > MISSED_WARN:
        chain = int(np.argmax(diag["missed_mass_per_chain"]))
        problems.append(
            f"MCMC chains disagree: chain {chain} never reached specifications holding "
            f"{worst:.1%} of the mass the chains found (> {MISSED_WARN:.0%}; "
            "mcmc_diagnostics_['missed_mass_per_chain']: neither visited them nor led to "
            "them from a state it visited through weighed neighbours), so the reported "
            "posterior is unreliable.")
    if not listed and diag.get("inclusion_rhat", 1.0) > RHAT_WARN:
        problems.append(
            "MCMC chains disagree: the posterior, too diffuse to list, is reported by their "
            "samples, and the split-R-hat of a clause's inclusion across them is "
            f"{diag['inclusion_rhat']:.3g} (> {RHAT_WARN}; mcmc_diagnostics_"
            "['inclusion_rhat']), so the reported posterior is unreliable.")
    if diag["rhat"] > RHAT_WARN:  # nan (too few samples) does not warn
        problems.append(
            f"MCMC chains have not mixed: the split-R-hat of their log posteriors is "
            f"{diag['rhat']:.3g} (> {RHAT_WARN}; mcmc_diagnostics_['rhat']).")
    return problems
