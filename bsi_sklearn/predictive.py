"""The posterior predictive: ``P(label = acceptable | demonstration, data)``, label noise included.

Every specification ``phi`` of the posterior labels a demonstration it satisfies acceptable
with probability ``1 - rho_phi`` and one it violates acceptable with probability ``rho_phi``
(the flip rate). ``rho_phi`` is the likelihood's ``epsilon`` for CB, CI and the calibrated
likelihood; with ``flip_prior=(a, b)`` it is the posterior mean of the flip rate given ``phi``,
Beta(a + v_phi, b + n - v_phi) restricted to (0, 1/2) as the likelihood's prior is
(:mod:`bsi_sklearn.model.flip_rate`), where ``v_phi`` is the number of training
demonstrations ``phi`` misclassifies; without one (``label_noise="learned"``), the uniform
prior's ``(1 + v_phi) / (2 + n)``. The predictive is the posterior mixture of these label models
(derivation: ``docs/likelihoods.md``, "The posterior predictive").

The specifications are grouped by their flip rate (one group for a fixed ``epsilon``, one per
value of ``v_phi`` with a flip prior), so a demonstration needs only the posterior mass it
satisfies and the mass it violates in each group; everything after that is in log space, so
that ``epsilon = exp(-2000)`` still gives an exact ``log P`` of the label it makes unlikely.
"""

from typing import NamedTuple

import numpy as np
from numba import njit

from bsi_sklearn.model.clauses import pack_rows
from bsi_sklearn.model.flip_rate import truncated_mean
from bsi_sklearn.satisfaction import satisfied_masses, satisfies

__all__ = ["LabelNoise", "LEARNED_PRIOR", "fixed_noise", "learned_noise", "misclassified",
           "label_noise", "predictive_log_proba"]


class LabelNoise(NamedTuple):
    """The flip rate of every specification of a posterior, grouped by value.

    ``group[h]`` is the group of the ``h``-th specification; ``log_rho[g]`` and
    ``log1m_rho[g]`` are ``log(rho)`` and ``log(1 - rho)`` of group ``g``, each computed
    without cancellation.
    """

    group: np.ndarray      # (n_specs,) int64
    log_rho: np.ndarray    # (n_groups,)
    log1m_rho: np.ndarray  # (n_groups,)


def fixed_noise(n_specs, log_eps):
    """One flip rate ``epsilon = exp(log_eps)`` for every specification.

    Examples
    --------
    >>> noise = fixed_noise(3, -2000.0)
    >>> noise.group.tolist(), float(noise.log_rho[0]), float(noise.log1m_rho[0])
    ([0, 0, 0], -2000.0, -0.0)
    """
    log_eps = float(log_eps)
    # log(1 - e^x): expm1 near 0, log1p far from it (x = -2000 gives -0.0, not log(1 - 0)).
    log1m = np.log(-np.expm1(log_eps)) if log_eps > -np.log(2.0) else np.log1p(-np.exp(log_eps))
    return LabelNoise(np.zeros(n_specs, dtype=np.int64), np.array([log_eps]), np.array([log1m]))


def learned_noise(violations, n_demos, flip_prior, bounded=False):
    """Each specification's flip rate given the ``violations`` it makes on the training data.

    A specification misclassifying ``v`` of ``n`` demonstrations has the flip rate's posterior
    Beta(a + v, b + n - v); the probability that the next label is flipped is its mean,
    ``(a + v) / (a + b + n)``, or with ``bounded`` (the likelihood's flip prior, which keeps
    the rate under one half) the mean of that Beta restricted to (0, 1/2).

    Examples
    --------
    >>> noise = learned_noise([0, 2, 0], 8, (1.0, 9.0))
    >>> noise.group.tolist(), np.exp(noise.log_rho).round(4).tolist()
    ([0, 1, 0], [0.0556, 0.1667])
    >>> np.exp(learned_noise([8], 8, (1.0, 9.0), bounded=True).log_rho).round(4).tolist()
    [0.4073]
    """
    a, b = (float(x) for x in flip_prior)
    values, group = np.unique(np.asarray(violations, dtype=float), return_inverse=True)
    if bounded:
        rho = truncated_mean(a + values, b + n_demos - values)
        return LabelNoise(group.ravel().astype(np.int64), np.log(rho), np.log1p(-rho))
    log_total = np.log(a + b + n_demos)
    return LabelNoise(group.ravel().astype(np.int64), np.log(a + values) - log_total,
                      np.log(b + n_demos - values) - log_total)


@njit(cache=True, nogil=True)
def _misclassified(masks, truth_words, w_pos, w_neg):
    # Per specification: the acceptable rows it violates plus the unacceptable ones it
    # satisfies, each distinct clause-truth row weighted by its number of demonstrations.
    out = np.zeros(masks.shape[0])
    for h in range(masks.shape[0]):
        for i in range(truth_words.shape[0]):
            out[h] += w_neg[i] if satisfies(masks, h, truth_words, i) else w_pos[i]
    return out


def misclassified(masks, truth, y01):
    """Training demonstrations each specification misclassifies, from the clause truth.

    Exact inference counts them by posterior mass only, not per listed specification; this
    reads the clause truth ``fit`` already built (no trace is read again).

    Parameters
    ----------
    masks : ndarray of shape (n_specs, n_words), uint64
        The specifications' clause masks (``Posterior``'s).
    truth : ndarray of shape (n_demos, n_clauses)
        Clause truth of the training demonstrations.
    y01 : ndarray of shape (n_demos,)
        Their 0/1 labels.

    Returns
    -------
    violations : ndarray of shape (n_specs,), float
    """
    words = pack_rows(np.ascontiguousarray(truth, dtype=np.uint8))
    y01 = np.asarray(y01)
    # Demonstrations with the same clause truth are interchangeable: count each row once.
    rows, inverse = np.unique(words, axis=0, return_inverse=True)
    inverse = inverse.ravel()
    w_pos = np.bincount(inverse, weights=(y01 == 1).astype(float), minlength=len(rows))
    w_neg = np.bincount(inverse, weights=(y01 == 0).astype(float), minlength=len(rows))
    return _misclassified(masks, np.ascontiguousarray(rows), w_pos, w_neg)


#: The flip rate's prior of ``label_noise="learned"`` without a flip prior: uniform (Laplace).
LEARNED_PRIOR = (1.0, 1.0)


def label_noise(violations, n_demos, log_eps, flip_prior, mode="learned"):
    """The :class:`LabelNoise` of a fitted posterior.

    ``mode="learned"``: each specification's flip rate given the training demonstrations it
    misclassifies (``violations``, per specification), under the prior ``flip_prior`` where
    the likelihood has one (restricted to (0, 1/2), as there) and the uniform Beta(1, 1)
    otherwise. ``mode="likelihood"``: the
    likelihood's own, ``epsilon`` (or, with ``flip_prior``, the same as ``"learned"``).

    Examples
    --------
    >>> learned = label_noise([0, 1], 8, -55.0, None)            # Beta(1, 1): (1 + v) / 10
    >>> np.exp(learned.log_rho).round(3).tolist()
    [0.1, 0.2]
    >>> float(label_noise([0, 1], 8, -55.0, None, "likelihood").log_rho[0])
    -55.0
    """
    violations = np.asarray(violations, dtype=float)
    if mode == "likelihood" and flip_prior is None:
        return fixed_noise(len(violations), log_eps)
    if flip_prior is None:
        return learned_noise(violations, n_demos, LEARNED_PRIOR)
    return learned_noise(violations, n_demos, flip_prior, bounded=True)


def predictive_log_proba(masks, probs, truth_words, noise):
    """``log P(label | demonstration, data)`` of every demonstration, columns (0, 1).

    ``P(1 | x) = sum_g S_g (1 - rho_g) + V_g rho_g`` and ``P(0 | x) = sum_g V_g (1 - rho_g)
    + S_g rho_g``, with ``S_g`` / ``V_g`` the mass of group ``g`` that ``x`` satisfies /
    violates; both summed in log space, then normalised together so that the rows'
    probabilities sum to 1 to rounding.

    Parameters
    ----------
    masks : ndarray of shape (n_specs, n_words), uint64
        The specifications' clause masks.
    probs : ndarray of shape (n_specs,)
        Their posterior probabilities.
    truth_words : ndarray of shape (n_demos, n_words), uint64
        The demonstrations' packed clause truth.
    noise : LabelNoise

    Returns
    -------
    log_proba : ndarray of shape (n_demos, 2)

    Examples
    --------
    >>> masks = np.array([[1], [3]], dtype=np.uint64)    # clause 0; clauses 0 and 1
    >>> words = np.array([[1], [3]], dtype=np.uint64)    # x0 holds clause 0, x1 both
    >>> lp = predictive_log_proba(masks, np.array([0.5, 0.5]), words, fixed_noise(2, -2000.0))
    >>> np.exp(lp).round(3).tolist()                     # x0: half the mass satisfied
    [[0.5, 0.5], [0.0, 1.0]]
    >>> float(lp[1, 0])                                  # x1: only a flip makes it 0
    -2000.0
    """
    n_groups = len(noise.log_rho)
    sat, viol = satisfied_masses(masks, np.ascontiguousarray(probs, dtype=float), noise.group,
                                 n_groups, truth_words)
    with np.errstate(divide="ignore"):  # a group with no mass on one side: log 0 = -inf
        log_sat, log_viol = np.log(sat), np.log(viol)
    keep, flip = noise.log1m_rho[None, :], noise.log_rho[None, :]
    log_1 = np.logaddexp.reduce(np.concatenate([log_sat + keep, log_viol + flip], axis=1),
                                axis=1)
    log_0 = np.logaddexp.reduce(np.concatenate([log_viol + keep, log_sat + flip], axis=1),
                                axis=1)
    total = np.logaddexp(log_0, log_1)
    return np.column_stack([log_0 - total, log_1 - total])
