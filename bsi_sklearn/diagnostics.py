"""Convergence and agreement diagnostics: split-R-hat across chains, total variation."""

import math

import numpy as np

__all__ = ["split_rhat", "total_variation"]


def split_rhat(traces):
    """Split-R-hat (Gelman et al., BDA3) of a scalar across chains.

    Parameters
    ----------
    traces : ndarray of shape (n_chains, n_draws)

    Returns
    -------
    float
        1.0 when every draw is identical (a chain that never moves off a sharp mode); ``inf``
        when chains sit on different constant values; ``nan`` with fewer than 4 draws.

    Examples
    --------
    >>> import numpy as np
    >>> split_rhat(np.zeros((2, 10)))
    1.0
    >>> split_rhat(np.array([[0.0] * 10, [1.0] * 10]))
    inf
    """
    traces = np.asarray(traces, dtype=float)
    n_draws = traces.shape[1]
    half = n_draws // 2
    if half < 2:
        return float("nan")
    split = np.concatenate([traces[:, :half], traces[:, half:2 * half]], axis=0)
    finite = np.isfinite(split)
    if not finite.all():
        return float("nan")
    # The log posterior is tracked incrementally: differences at rounding level are no signal.
    if np.ptp(split) <= 1e-9 * max(1.0, float(np.abs(split).max())):
        return 1.0
    means = split.mean(axis=1)
    within = split.var(axis=1, ddof=1).mean()
    between = half * means.var(ddof=1)
    if within == 0:
        return 1.0 if between == 0 else float("inf")
    var_plus = (half - 1) / half * within + between / half
    return float(np.sqrt(var_plus / within))


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
