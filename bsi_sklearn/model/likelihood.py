"""The likelihoods of BSI, in log space, from counts (derivations: ``docs/likelihoods.md``).

Complexity-based (CB, code 0) and complexity-independent (CI, code 1) as in the paper; CI with
the flip rate integrated over a Beta prior (code 2); the size principle calibrated by the data
(code 3), and the same with label flips as a model and their rate integrated (code 4). Codes 2
to 4 depend on the satisfied positives and negatives jointly.
"""

import math
import numbers

import numpy as np
from numba import njit

from bsi_sklearn._jit import helper
from bsi_sklearn.model.state_layout import max_conjuncts

__all__ = ["default_log_epsilon", "resolve_log_epsilon", "log_likelihood", "log_likelihood_cb",
           "cb_rejected", "LIKELIHOODS",
           "likelihood_code", "is_flip_prior", "resolve_flip_prior", "splits_by_label",
           "depends_on_conjuncts", "step_scale", "log_likelihood_reference",
           "flip_rate_posterior"]

LIKELIHOODS = ("cb", "ci", "calibrated")
_LIKELIHOOD_CODE = {"cb": 0, "ci": 1, "calibrated": 3}
#: Code of ``"ci"`` with a Beta prior on the flip rate (``flip_prior=(a, b)``).
_CI_FLIP_CODE = 2
#: Code of ``"calibrated"`` with a Beta prior on the flip rate.
_CALIBRATED_FLIP_CODE = 4


def default_log_epsilon(n_globals, n_subtasks):
    """Paper default ``log eps = -4 log(2) M`` with ``M = |T| + |Omega| + |Omega|(|Omega|-1)/2``.

    One violating demonstration then cancels the evidence of four satisfying ones.

    Examples
    --------
    >>> round(default_log_epsilon(5, 5), 4)
    -55.4518
    """
    m = max_conjuncts(n_globals, n_subtasks)  # the most conjuncts of a hypothesis
    return -4.0 * math.log(2.0) * m


def resolve_log_epsilon(epsilon, n_globals, n_subtasks):
    """``log(epsilon)`` for a user value in (0, 1), or the paper's default for ``None``."""
    if epsilon is None:
        # The default must stay a usable probability even for a tiny template (M = 0).
        return min(default_log_epsilon(n_globals, n_subtasks), math.log(0.5))
    return math.log(epsilon)


def likelihood_code(likelihood, flip_prior=None):
    """Integer code of a likelihood name (and flip prior) for the kernels."""
    if flip_prior is not None:
        resolve_flip_prior(likelihood, flip_prior)
        return _CI_FLIP_CODE if likelihood == "ci" else _CALIBRATED_FLIP_CODE
    return _LIKELIHOOD_CODE[likelihood]


def is_flip_prior(value):
    """Whether ``value`` is a pair ``(a, b)`` of positive finite numbers (not booleans).

    Examples
    --------
    >>> is_flip_prior((1, 9)), is_flip_prior((0, 1)), is_flip_prior((True, 1)), is_flip_prior(1)
    (True, False, False, False)
    """
    if not isinstance(value, (tuple, list)) or len(value) != 2:
        return False
    return all(isinstance(v, numbers.Real) and not isinstance(v, (bool, np.bool_))
               and 0.0 < float(v) < math.inf for v in value)


def resolve_flip_prior(likelihood, flip_prior, epsilon=None):
    """``(a, b)`` of the flip rate's Beta prior as floats; ``(0.0, 0.0)`` for none.

    Raises
    ------
    ValueError
        When the prior is given with CB (not normalised over the labels, so a prior on its
        epsilon has no meaning), together with ``epsilon`` (which it replaces), or is not a
        pair of positive finite numbers.

    Examples
    --------
    >>> resolve_flip_prior("ci", (1, 9))
    (1.0, 9.0)
    >>> resolve_flip_prior("cb", None)
    (0.0, 0.0)
    """
    if flip_prior is None:
        return 0.0, 0.0
    if likelihood not in ("ci", "calibrated"):
        raise ValueError(
            f"flip_prior applies to the likelihoods 'ci' and 'calibrated', not "
            f"likelihood={likelihood!r}: CB is not normalised over the labels, so its epsilon "
            "is a penalty, not a flip rate with a prior")
    if epsilon is not None:
        raise ValueError(f"flip_prior={flip_prior!r} integrates the flip rate out: leave "
                         f"epsilon=None (got epsilon={epsilon!r})")
    if not is_flip_prior(flip_prior):
        raise ValueError(f"flip_prior must be a pair (a, b) of positive finite numbers, got "
                         f"{flip_prior!r}")
    return float(flip_prior[0]), float(flip_prior[1])


def splits_by_label(code):
    """Whether the log-likelihood of ``code`` is a sum of a positives' and a negatives' term.

    True for CB and CI; the others depend on the two counts jointly.
    """
    return code in (0, 1)


def depends_on_conjuncts(code):
    """Whether the likelihood of ``code`` depends on the number of conjuncts (CB only)."""
    return code == 0


def step_scale(code, log_eps, n_pos, n_neg, flips):
    """The largest change of the log-likelihood by one demonstration or one conjunct.

    What the MCMC's temperature ladder spans (``mcmc.temperature_ladder``): ``|log eps|``
    for a demonstration changing side; for CB also ``n_pos log 2`` for a conjunct; with the
    flip rate integrated, the largest step of its table ``flips`` by one misclassified
    demonstration more (the first costs about ``log((b + n - 1) / a)``); the calibrated
    likelihood also moves every correctly classified demonstration by up to ``log(n + 2)``
    when one demonstration changes side (code 4: that on top of the flips' step).
    """
    n = n_pos + n_neg
    if code == 0:
        return max(-log_eps, n_pos * math.log(2.0))
    if code in (_CI_FLIP_CODE, _CALIBRATED_FLIP_CODE):
        step = float(np.max(np.abs(np.diff(flips)))) if len(flips) > 1 else 0.0
        return step if code == _CI_FLIP_CODE else step + math.log(n + 2.0)
    if code == 3:
        return -log_eps + math.log(n + 2.0)
    return -log_eps


@helper
def _log1mexp(x):
    # log(1 - exp(x)) for x < 0, accurate near 0 and for very negative x.
    if x > -0.6931471805599453:
        return math.log(-math.expm1(x))
    return math.log1p(-math.exp(x))


@helper
def _log_flips(wrong, flips):
    # The labels' flip rate integrated over its Beta(a, b) prior restricted to (0, 1/2)
    # (codes 2 and 4), tabled by the number v = wrong of misclassified demonstrations
    # (bsi_sklearn.model.flip_rate.log_flip_marginals): counts are whole numbers.
    return flips[int(wrong + 0.5)]


@njit(cache=True, nogil=True)
def cb_rejected(n_conj):
    """CB's log-likelihood of an unacceptable demonstration the formula violates.

    ``log(2^N / (2^N - 1)) = -log(1 - 2^-N)``; a violated formula has ``N >= 1``. The MCMC's
    moves keep it in a table by ``N`` (the same numbers, without a ``log1p`` per candidate).
    """
    return -_log1mexp(-n_conj * 0.6931471805599453)


@njit(cache=True, nogil=True, inline="always")
def log_likelihood_cb(pos_sat, neg_sat, n_pos, n_neg, n_conj, log_eps, rejected):
    """:func:`log_likelihood` of CB, given ``rejected = cb_rejected(n_conj)``."""
    out = pos_sat * (n_conj * 0.6931471805599453) + (n_pos - pos_sat) * log_eps \
        + neg_sat * log_eps
    neg_viol = n_neg - neg_sat
    if neg_viol > 0.0:
        out += neg_viol * rejected
    return out


@njit(cache=True, nogil=True)
def log_likelihood(pos_sat, neg_sat, n_pos, n_neg, n_conj, log_eps, code, flips):
    """Log-likelihood of a dataset given a formula, from counts.

    Parameters
    ----------
    pos_sat, neg_sat : float
        (Weighted) numbers of acceptable / unacceptable demonstrations the formula satisfies.
    n_pos, n_neg : float
        Numbers of acceptable / unacceptable demonstrations.
    n_conj : int
        Number of conjuncts ``N`` of the formula.
    log_eps : float
        ``log(epsilon)`` (unused by codes 2 and 4).
    code : int
        0 ``"cb"``, 1 ``"ci"``, 2 ``"ci"`` with the flip rate integrated over a Beta(a, b)
        prior, 3 ``"calibrated"``, 4 ``"calibrated"`` with the flip rate integrated.
    flips : ndarray of float
        Codes 2 and 4: the labels' log marginal likelihood by number of misclassified
        demonstrations, ``0 .. n_pos + n_neg`` (``Model.flips``:
        :func:`bsi_sklearn.model.flip_rate.log_flip_marginals`); unused by the others.

    Returns
    -------
    float
    """
    pos_viol = n_pos - pos_sat
    neg_viol = n_neg - neg_sat
    if code == 0:
        return log_likelihood_cb(pos_sat, neg_sat, n_pos, n_neg, n_conj, log_eps,
                                 cb_rejected(n_conj) if neg_viol > 0.0 else 0.0)
    if code == 1:
        log1m_eps = _log1mexp(log_eps)
        return (pos_sat + neg_viol) * log1m_eps + (pos_viol + neg_sat) * log_eps
    wrong = pos_viol + neg_sat
    if code == 2:
        return _log_flips(wrong, flips)
    log_n2 = math.log(n_pos + n_neg + 2.0)
    sat = pos_sat + neg_sat
    # Calibrated size principle: the mass of ext(phi) estimated from every demonstration,
    # m = (s + 1) / (n + 2); an accepted satisfying demonstration earns 1 / m, a rejected
    # violating one 1 / (1 - m), a misclassified one epsilon (code 3) or, code 4, each label
    # is right with 1 - eps and flipped with eps, eps integrated over Beta(a, b).
    if code == 4:
        out = _log_flips(wrong, flips)
    else:
        out = wrong * log_eps
    if pos_sat > 0.0:
        out += pos_sat * (log_n2 - math.log(sat + 1.0))
    if neg_viol > 0.0:
        out += neg_viol * (log_n2 - math.log(n_pos + n_neg - sat + 1.0))
    return out


def log_likelihood_reference(satisfied, y, n_conj, log_eps, likelihood, flip_prior=None):
    """Per-demonstration reference implementation (plain Python), for tests and docs.

    Parameters
    ----------
    satisfied : array-like of bool
        Whether each demonstration satisfies the formula.
    y : array-like of {0, 1}
        Labels.
    n_conj : int
    log_eps : float
    likelihood : {"cb", "ci", "calibrated"}
    flip_prior : tuple of float, default=None
        ``(a, b)``: the flip rate integrated over a Beta(a, b) prior restricted to (0, 1/2)
        (scipy's incomplete Beta function, not the kernels' table); with ``"calibrated"``,
        times the density ``1 / m`` or ``1 / (1 - m)`` of each correctly classified
        demonstration.

    Returns
    -------
    float
    """
    from scipy.special import betainc, betaln

    sat_all = np.asarray(satisfied, bool)
    labels = np.asarray(y)
    m = (sat_all.sum() + 1.0) / (len(sat_all) + 2.0)
    if flip_prior is not None:
        a, b = (float(x) for x in flip_prior)
        bad = sat_all != (labels == 1)
        v, r = float(bad.sum()), float((~bad).sum())
        total = (betaln(a + v, b + r) + math.log(betainc(a + v, b + r, 0.5))
                 - betaln(a, b) - math.log(betainc(a, b, 0.5)))
        if likelihood == "calibrated":
            for s, wrong in zip(sat_all, bad):
                if not wrong:
                    total -= math.log(m) if s else math.log1p(-m)
        return float(total)
    total = 0.0
    for s, label in zip(sat_all, labels):
        if likelihood == "cb":
            if label == 1:
                total += n_conj * math.log(2) if s else log_eps
            else:
                total += log_eps if s else math.log(2.0**n_conj / (2.0**n_conj - 1))
        elif likelihood == "calibrated":
            if label == 1:
                total += -math.log(m) if s else log_eps
            else:
                total += log_eps if s else -math.log(1.0 - m)
        else:
            ok = s if label == 1 else not s
            total += math.log1p(-math.exp(log_eps)) if ok else log_eps
    return total


def flip_rate_posterior(violations, weights, n_demos, flip_prior, level=0.95):
    """Posterior mean and central interval of the flip rate under a Beta(a, b) prior.

    The prior is restricted to (0, 1/2) (:mod:`bsi_sklearn.model.flip_rate`): given a
    hypothesis that misclassifies ``v`` of ``n`` demonstrations, the flip rate's posterior is
    Beta(a + v, b + n - v) restricted there; over the posterior of the hypotheses it is the
    mixture of those weighted by the posterior mass of each ``v``.

    Parameters
    ----------
    violations : array-like of float
        Numbers of misclassified demonstrations ``v`` (acceptable ones the formula violates
        plus unacceptable ones it satisfies).
    weights : array-like of float
        Posterior mass of each entry of ``violations`` (normalised here).
    n_demos : int
        Number of demonstrations ``n``.
    flip_prior : tuple of float or None
        ``(a, b)``; ``None`` returns ``(None, None)``.
    level : float, default=0.95
        Mass of the central interval.

    Returns
    -------
    mean : float
    interval : tuple of float
        The ``(1 - level) / 2`` and ``(1 + level) / 2`` quantiles of the mixture (bisection on
        its distribution function, to 1e-12).

    Examples
    --------
    >>> mean, (lo, hi) = flip_rate_posterior([0], [1.0], 8, (1.0, 1.0))
    >>> round(mean, 4), round(lo, 4), round(hi, 4)   # Beta(1, 9) on (0, 1/2)
    (0.0991, 0.0028, 0.3308)
    """
    from bsi_sklearn.model.flip_rate import HALF, log_betainc, truncated_mean

    if flip_prior is None:
        return None, None
    a, b = (float(x) for x in flip_prior)
    v = np.asarray(violations, dtype=float)
    w = np.asarray(weights, dtype=float)
    keep = w > 0
    v, w = v[keep], w[keep] / w[keep].sum()
    # one mixture component per distinct v
    v, inverse = np.unique(v, return_inverse=True)
    w = np.bincount(inverse.ravel(), weights=w, minlength=len(v))
    alpha, beta = a + v, b + n_demos - v
    mean = float(w @ truncated_mean(alpha, beta))
    log_norm = log_betainc(alpha, beta, HALF)

    def quantile(q):
        lo, hi = 0.0, HALF
        while hi - lo > 1e-12:
            mid = 0.5 * (lo + hi)
            if float(w @ np.exp(log_betainc(alpha, beta, mid) - log_norm)) < q:
                lo = mid
            else:
                hi = mid
        return 0.5 * (lo + hi)

    return mean, (quantile((1.0 - level) / 2.0), quantile((1.0 + level) / 2.0))
