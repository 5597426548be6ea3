"""The labels' flip rate: a Beta prior truncated to (0, 1/2), integrated out.

A flip rate above one half says the labels are mostly wrong: with it, a formula that
misclassifies every demonstration explains them as well as one that classifies them all
correctly (each label flipped), so the posterior would hold formulas that read the opposite of
the data wherever the template cannot state the rule. The rate therefore lies in (0, 1/2): the
prior is Beta(a, b) restricted there and renormalised. Given a formula that misclassifies
``v`` of ``n`` demonstrations, the marginal likelihood of the labels is

    ∫_0^½ ε^v (1 − ε)^(n − v) Beta(ε; a, b) dε / ∫_0^½ Beta(ε; a, b) dε
        = B(a + v, b + n − v) I_½(a + v, b + n − v) / (B(a, b) I_½(a, b)),

``I_x`` the regularised incomplete Beta function, and the rate's posterior is
Beta(a + v, b + n − v) restricted to (0, 1/2). ``I_½`` is computed here in log space by its
continued fraction (Numerical Recipes' ``betacf``, with Lentz's method): for ``v`` well above
``n / 2`` it is far below the smallest float.
"""

import numpy as np
from scipy.special import betaln

__all__ = ["log_betainc", "log_flip_marginals", "truncated_mean", "HALF"]

#: The flip rate's upper bound.
HALF = 0.5

_EPS = 1e-16
_TINY = 1e-300
_MAX_ITER = 100_000


def _nonzero(v):
    # Lentz's method: a vanishing denominator is replaced by a tiny one.
    return np.where(np.abs(v) < _TINY, _TINY, v)


def _log_cf(a, b, x):
    """Log of I_x(a, b)'s continued fraction, vectorised (converges where x < (a+1)/(a+b+2)).

    Entries leave the iteration as they converge: far from ``x = a / (a + b)`` a few terms
    suffice, near it about ``sqrt(a + b)``, so a table over every ``v`` costs little more than
    its slowest entries.
    """
    out = np.empty(a.shape)
    qab, qap, qam = a + b, a + 1.0, a - 1.0
    c = np.ones_like(a)
    d = 1.0 / _nonzero(1.0 - qab * x / qap)
    h = d.copy()
    live = np.arange(len(a))
    for m in range(1, _MAX_ITER + 1):
        m2 = 2.0 * m
        aa = m * (b - m) * x / ((qam + m2) * (a + m2))
        d = 1.0 / _nonzero(1.0 + aa * d)
        c = _nonzero(1.0 + aa / c)
        h = h * d * c
        aa = -(a + m) * (qab + m) * x / ((a + m2) * (qap + m2))
        d = 1.0 / _nonzero(1.0 + aa * d)
        c = _nonzero(1.0 + aa / c)
        step = d * c
        h = h * step
        done = np.abs(step - 1.0) < _EPS
        if done.any():
            out[live[done]] = np.log(h[done])
            keep = ~done
            if not keep.any():
                return out
            live, a, b, qab, qap, qam, c, d, h = (
                v[keep] for v in (live, a, b, qab, qap, qam, c, d, h))
    raise RuntimeError("the incomplete Beta function's continued fraction did not converge")


def _log_direct(a, b, x):
    # log I_x(a, b) = log[x^a (1 - x)^b / (a B(a, b))] + log CF(a, b, x), 1-D arrays, where the
    # fraction converges (x < (a + 1) / (a + b + 2)).
    return a * np.log(x) + b * np.log1p(-x) - betaln(a, b) - np.log(a) + _log_cf(a, b, x)


def log_betainc(a, b, x):
    """``log I_x(a, b)``, the regularised incomplete Beta function, accurate where it is tiny.

    Parameters
    ----------
    a, b : array-like of float
        Positive shape parameters (broadcast together).
    x : float
        In (0, 1).

    Returns
    -------
    ndarray of float

    Examples
    --------
    >>> from scipy.special import betainc
    >>> bool(np.isclose(np.exp(log_betainc(3.0, 5.0, 0.5)), betainc(3.0, 5.0, 0.5)))
    True
    >>> float(log_betainc(2000.0, 10.0, 0.5)) < -1300   # below the smallest float
    True
    """
    a, b = np.broadcast_arrays(np.asarray(a, dtype=float), np.asarray(b, dtype=float))
    x = float(x)
    direct = x < (a + 1.0) / (a + b + 2.0)
    out = np.empty(a.shape)
    if direct.any():
        out[direct] = _log_direct(a[direct], b[direct], x)
    # Elsewhere 1 - I_(1-x)(b, a), whose fraction converges (the complement is under one half).
    if (~direct).any():
        out[~direct] = np.log1p(-np.exp(_log_direct(b[~direct], a[~direct], 1.0 - x)))
    return out


def log_flip_marginals(n_demos, a, b):
    """The labels' log marginal likelihood for each number ``v = 0 .. n`` of misclassified ones.

    ``log[B(a + v, b + n − v) I_½(a + v, b + n − v) / (B(a, b) I_½(a, b))]``: the flip rate
    Beta(a, b) restricted to (0, 1/2) and integrated out (module docstring). The likelihood
    kernels read it by ``v``.

    Examples
    --------
    >>> t = log_flip_marginals(4, 1.0, 1.0)   # uniform on (0, 1/2)
    >>> bool(np.isclose(np.exp(t[0]), 2 * (1 - 0.5 ** 5) / 5))   # 2 ∫_0^½ (1 - e)^4 de
    True
    >>> bool(t[4] < t[0])   # misclassifying all is less likely than none
    True
    """
    n = int(n_demos)
    v = np.arange(n + 1, dtype=float)
    alpha, beta = a + v, b + n - v
    norm = betaln(a, b) + log_betainc(a, b, HALF)[()]
    return betaln(alpha, beta) + log_betainc(alpha, beta, HALF) - norm


def truncated_mean(alpha, beta):
    """Mean of Beta(alpha, beta) restricted to (0, 1/2), vectorised.

    ``alpha / (alpha + beta) · I_½(alpha + 1, beta) / I_½(alpha, beta)``.

    Examples
    --------
    >>> round(float(truncated_mean(1.0, 1.0)), 6)   # uniform on (0, 1/2)
    0.25
    """
    alpha, beta = np.broadcast_arrays(np.asarray(alpha, dtype=float),
                                      np.asarray(beta, dtype=float))
    return np.exp(np.log(alpha) - np.log(alpha + beta) + log_betainc(alpha + 1.0, beta, HALF)
                  - log_betainc(alpha, beta, HALF))
