"""Active learning: which unlabelled demonstrations to ask a teacher about first.

Query strategies in the style of modAL's (``strategy(classifier, X_pool, n_instances)``),
for a fitted :class:`~bsi_sklearn.BSIClassifier`.
"""

from __future__ import annotations

import numbers

import numpy as np
from sklearn.utils.validation import check_is_fitted

from bsi_sklearn.param_validation import Interval, validate_params

__all__ = ["entropy_sampling", "vote_entropy"]


def vote_entropy(clf, X):
    """Entropy (bits) of the posterior vote on each demonstration.

    Parameters
    ----------
    clf : BSIClassifier
        A fitted classifier.
    X : demonstrations, in any format accepted by :meth:`BSIClassifier.fit`.

    Returns
    -------
    entropy : ndarray of shape (n_demos,)
        ``H(p) = -p log2 p - (1 - p) log2 (1 - p)`` with ``p`` the posterior mass of the
        formulas a demonstration satisfies (``predict_proba`` under ``vote="satisfaction"``,
        whatever ``clf.vote``): 0 when the posterior agrees, 1 bit when it is split in half.

    Examples
    --------
    >>> import numpy as np
    >>> from bsi_sklearn import BSIClassifier
    >>> X = [np.array([[1, 0], [1, 1]])]
    >>> clf = BSIClassifier(random_state=0).fit(X)
    >>> vote_entropy(clf, [np.array([[1, 0], [1, 1]])]).round(3)
    array([0.])
    """
    # The vote, not the predictive: the label noise would add the same entropy to every score.
    p = np.clip(clf.posterior_.predict_proba(clf._validated(X))[:, 1], 0.0, 1.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        h = -(p * np.log2(p) + (1 - p) * np.log2(1 - p))
    return np.nan_to_num(h, nan=0.0)


def entropy_sampling(clf, X_pool, n_instances=1):
    """Indices of the pool demonstrations whose label would tell most about the formula.

    Under posterior voting every formula labels a demonstration deterministically (it
    satisfies the formula or not), so the label ``y`` of a demonstration is a function of the
    formula ``phi``: ``H(y | phi) = 0`` and the information the label gives about the formula,
    ``I(y; phi) = H(y) - H(y | phi)``, is the entropy of the vote ``H(y)``. Asking for the
    demonstrations with the highest vote entropy is therefore both uncertainty sampling and
    the Bayesian active-learning (BALD) choice, here with no approximation. (The likelihood's
    small ``epsilon`` makes labels slightly noisy; it lowers every score by the same amount
    and leaves the ranking unchanged, so the scores are the vote's, not ``predict_proba``'s
    posterior predictive.)

    Parameters
    ----------
    clf : BSIClassifier
        A fitted classifier.
    X_pool : demonstrations
        The unlabelled pool, in any format accepted by :meth:`BSIClassifier.fit`.
    n_instances : int, default=1
        How many demonstrations to return (at most the size of the pool).

    Returns
    -------
    indices : ndarray of shape (n_instances,)
        Positions in ``X_pool``, most informative first; ties keep the pool's order.

    See Also
    --------
    vote_entropy : the scores.

    Examples
    --------
    >>> import numpy as np
    >>> from bsi_sklearn import BSIClassifier
    >>> # propositions: a, b. One demonstration does a, then b; both may be subtasks.
    >>> clf = BSIClassifier(roles="all", random_state=0).fit([np.array([[1, 0], [1, 1]])])
    >>> pool = [np.array([[1, 0], [1, 1]]),   # what was shown: no news
    ...         np.array([[0, 1], [1, 1]]),   # b before a: does the order matter?
    ...         np.array([[0, 0], [0, 0]])]   # nothing done: almost surely bad
    >>> vote_entropy(clf, pool).round(2)
    array([0.  , 0.44, 0.04])
    >>> entropy_sampling(clf, pool)
    array([1])
    """
    check_is_fitted(clf)
    validate_params({"n_instances": n_instances},
                    {"n_instances": [Interval(numbers.Integral, 1, None, closed="left")]},
                    "entropy_sampling")
    h = vote_entropy(clf, X_pool)
    if n_instances > len(h):
        raise ValueError(
            f"entropy_sampling: n_instances={n_instances} is more than the {len(h)} "
            "demonstrations of the pool"
        )
    return np.argsort(-h, kind="stable")[:n_instances]
