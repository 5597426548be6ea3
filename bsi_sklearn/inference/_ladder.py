"""The chains' temperature ladder: the default one, and the one adapted to the posterior.

:func:`temperature_ladder` spans the likelihood's largest step (one rung per halving of beta);
:func:`adapted_ladder` keeps its ends and sheds the rungs the posterior does not need, from the
swap rejection rates a pilot measured on it (non-reversible parallel tempering's schedule
adaptation: Syed, Bouchard-Cote, Deligiannidis & Doucet, 2022, *Non-reversible parallel
tempering: a scalable highly parallel MCMC scheme*, JRSS B 84(2), sections 4-5).
"""

import math

import numpy as np

from bsi_sklearn.model.likelihood import step_scale

__all__ = ["LADDER_RATIO", "PILOT_MIN", "temperature_ladder", "adapted_ladder", "swap_tries",
           "pilot_rejection"]

#: Ratio of adjacent inverse temperatures of the default ladder.
LADDER_RATIO = 0.5
#: Fewest burn-in sweeps the ladder is adapted on; with fewer, the default ladder is kept.
PILOT_MIN = 20


def temperature_ladder(demos, model, n_temperatures="auto"):
    """Inverse temperatures of a chain's replicas, ``1`` first, geometric.

    The likelihood moves in steps of two sizes: a demonstration that changes side costs or
    gains about ``|log eps|``, and (CB likelihood) a conjunct more or less changes every
    satisfied acceptable demonstration by ``log 2``. With ``L = max(|log eps|, n_pos log 2)``
    (``n_pos``: acceptable demonstrations; the second term for CB only), the hottest replica
    has ``beta = 1 / L``, where one such step costs at most about one nat, so that it moves
    nearly as freely as the prior; the rungs halve beta (``LADDER_RATIO``), which gives
    ``"auto"`` ``1 + ceil(log2 L)`` rungs (one when ``L <= 1``). The other likelihoods'
    steps are in :func:`bsi_sklearn.model.likelihood.step_scale`. An integer sets the number
    of rungs (1: no tempering), spread geometrically between 1 and ``1 / L``. The sampler
    adapts the ``"auto"`` ladder to the posterior (:func:`adapted_ladder`).

    Examples
    --------
    >>> from bsi_sklearn.model import make_model
    >>> from bsi_sklearn.inference.mcmc import deduplicate_demos
    >>> import numpy as np
    >>> m = make_model(prior="sets_of_chains", likelihood="cb", n_globals=2, n_subtasks=2)
    >>> d = deduplicate_demos(np.eye(3, 8, dtype=np.uint8), np.ones(3))
    >>> temperature_ladder(d, m).round(4).tolist()   # |log eps| = 4 log(2) 5 = 13.9
    [1.0, 0.5, 0.25, 0.125, 0.0721]
    >>> temperature_ladder(d, m, 1).tolist()
    [1.0]
    """
    scale = step_scale(model.likelihood, model.log_eps, demos.n_pos, demos.n_neg,
                       model.flips)
    if n_temperatures == "auto":
        if scale <= 1.0:  # one rung, at beta = 1 (1 / scale, above 1, would sharpen the target)
            return np.ones(1)
        n_rungs = 1 + math.ceil(math.log(scale) / -math.log(LADDER_RATIO))
        return np.maximum(LADDER_RATIO ** np.arange(n_rungs), 1.0 / scale)
    n_rungs = int(n_temperatures)
    if n_rungs == 1 or scale <= 1.0:
        return np.ones(n_rungs)
    return np.exp(-np.log(scale) * np.arange(n_rungs) / (n_rungs - 1))


def swap_tries(n_sweeps, n_pairs):
    """Swaps each pair of adjacent rungs proposed in ``n_sweeps`` sweeps.

    Pair ``k`` proposes after the sweeps of ``k``'s parity: the even pairs after sweep 0, the
    odd after sweep 1, and so on.
    """
    return (int(n_sweeps) + 1 - np.arange(n_pairs) % 2) // 2


def adapted_ladder(betas, rejection):
    """The ladder with as few rungs as the measured swap rejections call for.

    ``rejection[k]`` is the mean rejection probability of swaps between rungs ``k`` and
    ``k + 1`` of ``betas`` (decreasing, ``betas[0] = 1``). Their running sum is the
    communication barrier ``Lambda(beta)``, taken piecewise linear in ``log beta`` between the
    rungs; its total ``Lambda`` says how hard the ladder is to cross. Non-reversible parallel
    tempering (even and odd pairs in turn, as the chain kernel swaps) spends the least work per
    round trip of a replica from the coldest rung to the hottest and back with about
    ``2 Lambda`` intervals, each rejecting about half its swaps (Syed et al. 2022, section 5).
    The adapted ladder keeps both ends (beta = 1 and the hottest, which crosses the valleys)
    and puts ``1 + ceil(2 Lambda)`` rungs, at least 2 and at most ``len(betas)``, at equal
    steps of ``Lambda(beta)``. With as many rungs as before it is ``betas`` itself: the
    adaptation only sheds rungs, so it never costs more than the default ladder.

    Examples
    --------
    >>> betas = 0.5 ** np.arange(8)
    >>> adapted_ladder(betas, np.zeros(7)).tolist()   # every swap accepted: two rungs
    [1.0, 0.0078125]
    >>> adapted_ladder(betas, np.array([0, 0, 0, 0.5, 0.5, 0, 0])).round(4).tolist()
    [1.0, 0.0625, 0.0078]
    """
    betas = np.asarray(betas, dtype=np.float64)
    rejection = np.clip(np.asarray(rejection, dtype=np.float64), 0.0, 1.0)
    if len(betas) <= 2:
        return betas
    barrier = np.concatenate([[0.0], np.cumsum(rejection)])
    total = float(barrier[-1])
    n_rungs = min(len(betas), max(2, 1 + math.ceil(2.0 * total - 1e-9)))
    if n_rungs == len(betas):
        return betas
    log_b = np.log(betas)
    out = np.empty(n_rungs)
    out[0], out[-1] = betas[0], betas[-1]
    for i in range(1, n_rungs - 1):
        level = total * i / (n_rungs - 1)
        # The first rung where the barrier reaches the level: it rose across (k - 1, k).
        k = int(np.searchsorted(barrier, level, side="left"))
        f = (level - barrier[k - 1]) / (barrier[k] - barrier[k - 1])
        out[i] = math.exp(log_b[k - 1] + f * (log_b[k] - log_b[k - 1]))
    return out


def pilot_rejection(pilots, n_sweeps, n_jobs=None):
    """Each pair of rungs' mean swap rejection probability, measured by running ``pilots``.

    ``pilots`` are chains (``mcmc.ChainRun``) on one ladder; each runs ``n_sweeps`` sweeps
    (in threads). The rate is that of the second half (the first leaves the optimum every
    replica starts from), from the acceptance probabilities the kernel sums (``ChainLoop.
    accept``: the counted swaps' mean, with less noise), all chains pooled, so that every
    chain gets the same ladder whatever ``n_jobs``.
    """
    from sklearn.utils.parallel import Parallel, delayed

    half = n_sweeps // 2
    n_pairs = len(pilots[0].betas) - 1
    with Parallel(n_jobs=n_jobs, backend="threading") as parallel:
        parallel(delayed(run.advance)(half) for run in pilots)
        before = [run.loop.accept.copy() for run in pilots]
        parallel(delayed(run.advance)(n_sweeps - half) for run in pilots)
    tries = (swap_tries(n_sweeps, n_pairs) - swap_tries(half, n_pairs)) * len(pilots)
    accepted = sum(run.loop.accept - b for run, b in zip(pilots, before))
    return 1.0 - accepted / np.maximum(tries, 1)
