"""Complexity-based (CB) and complexity-independent (CI) likelihoods, in log space."""

import math

import numpy as np
from numba import njit

__all__ = ["default_log_epsilon", "resolve_log_epsilon", "log_likelihood", "LIKELIHOODS"]

LIKELIHOODS = ("cb", "ci")
_LIKELIHOOD_CODE = {"cb": 0, "ci": 1}


def default_log_epsilon(n_globals, n_subtasks):
    """Paper default ``log eps = -4 log(2) M`` with ``M = |T| + |Omega| + |Omega|(|Omega|-1)/2``.

    One violating demonstration then cancels the evidence of four satisfying ones.

    Examples
    --------
    >>> round(default_log_epsilon(5, 5), 4)
    -55.4518
    """
    m = n_globals + n_subtasks + n_subtasks * (n_subtasks - 1) / 2
    return -4.0 * math.log(2.0) * m


def resolve_log_epsilon(epsilon, n_globals, n_subtasks):
    """``log(epsilon)`` for a user value in (0, 1), or the paper's default for ``None``."""
    if epsilon is None:
        # The default must stay a usable probability even for a tiny template (M = 0).
        return min(default_log_epsilon(n_globals, n_subtasks), math.log(0.5))
    return math.log(epsilon)


def likelihood_code(likelihood):
    """Integer code of a likelihood name for the kernels."""
    return _LIKELIHOOD_CODE[likelihood]


@njit(cache=True, nogil=True)
def _log1mexp(x):
    # log(1 - exp(x)) for x < 0, accurate near 0 and for very negative x.
    if x > -0.6931471805599453:
        return math.log(-math.expm1(x))
    return math.log1p(-math.exp(x))


@njit(cache=True, nogil=True)
def log_likelihood(pos_sat, neg_sat, n_pos, n_neg, n_conj, log_eps, code):
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
        ``log(epsilon)``.
    code : int
        0 for ``"cb"``, 1 for ``"ci"``.

    Returns
    -------
    float
    """
    pos_viol = n_pos - pos_sat
    neg_viol = n_neg - neg_sat
    if code == 0:
        out = pos_sat * (n_conj * 0.6931471805599453) + pos_viol * log_eps + neg_sat * log_eps
        if neg_viol > 0.0:
            # log(2^N / (2^N - 1)) = -log(1 - 2^-N); a violated formula has N >= 1.
            out += neg_viol * (-_log1mexp(-n_conj * 0.6931471805599453))
        return out
    log1m_eps = _log1mexp(log_eps)
    return (pos_sat + neg_viol) * log1m_eps + (pos_viol + neg_sat) * log_eps


def log_likelihood_reference(satisfied, y, n_conj, log_eps, likelihood):
    """Per-demonstration reference implementation (plain Python), for tests and docs.

    Parameters
    ----------
    satisfied : array-like of bool
        Whether each demonstration satisfies the formula.
    y : array-like of {0, 1}
        Labels.
    n_conj : int
    log_eps : float
    likelihood : {"cb", "ci"}

    Returns
    -------
    float
    """
    total = 0.0
    for s, label in zip(np.asarray(satisfied, bool), np.asarray(y)):
        if likelihood == "cb":
            if label == 1:
                total += n_conj * math.log(2) if s else log_eps
            else:
                total += log_eps if s else math.log(2.0**n_conj / (2.0**n_conj - 1))
        else:
            ok = s if label == 1 else not s
            total += math.log1p(-math.exp(log_eps)) if ok else log_eps
    return total
