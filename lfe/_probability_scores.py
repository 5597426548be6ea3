"""The probabilities of a row of ``bsi-lfe compare`` and ``study``, and their log loss and Brier.

A row has probabilities when its fitted model has ``predict_proba`` (BSI's posterior
predictive, the logistic regression, the networks, the majority class's base rate); the others
(MiniRocket's ridge classifier, the noise-free rule, a BSI fit that could not run) have none,
and their scores are ``nan``, written "n/a" in the tables: never a number made up for them.
"""

from __future__ import annotations

import numpy as np
from sklearn.metrics import brier_score_loss, log_loss

__all__ = ["NOT_AVAILABLE", "format_score", "positive_probabilities", "probability_scores"]

#: How the tables write the score of a row without probabilities.
NOT_AVAILABLE = "n/a"


def positive_probabilities(clf, X):
    """P(label 1) of every sequence and objective, or ``None`` without ``predict_proba``.

    Parameters
    ----------
    clf : fitted classifier
        One objective (``classes_`` an array, ``predict_proba`` an array) or several
        (``classes_`` and ``predict_proba`` lists, one entry per objective, as
        :class:`baselines.LSTMSequenceClassifier` and the practitioner's rows give them).
    X : sequences
        What ``clf.predict_proba`` reads.

    Returns
    -------
    proba : ndarray of shape (n_sequences, n_objectives) or None
        The column of label 1 (zeros when an objective's training labels were all 0: the
        model's single column is then the probability of 0).
    """
    if not hasattr(clf, "predict_proba"):
        return None
    proba, classes = clf.predict_proba(X), clf.classes_
    if not isinstance(proba, list):
        proba, classes = [proba], [classes]
    columns = []
    for p, labels in zip(proba, classes):
        labels = list(np.asarray(labels))
        columns.append(p[:, labels.index(1)] if 1 in labels else np.zeros(len(p)))
    return np.column_stack(columns).astype(float)


def probability_scores(y_true, p1):
    """Log loss and Brier score of P(label 1) against 0/1 labels; ``nan`` without ``p1``.

    scikit-learn's :func:`~sklearn.metrics.log_loss` (``labels=[0, 1]``, its own clipping
    only) and :func:`~sklearn.metrics.brier_score_loss`.

    Parameters
    ----------
    y_true : array-like of shape (n,)
        0/1 labels.
    p1 : array-like of shape (n,) or None
        P(label 1); ``None`` or any ``nan`` (a row or fold without probabilities) gives
        ``nan`` scores.

    Returns
    -------
    scores : dict
        ``{"log_loss": float, "brier": float}``.

    Examples
    --------
    >>> probability_scores([0, 1], [0.2, 0.9])["brier"]
    0.025
    >>> probability_scores([0, 1], None)
    {'log_loss': nan, 'brier': nan}
    """
    if p1 is None or np.isnan(np.asarray(p1, dtype=float)).any():
        return {"log_loss": float("nan"), "brier": float("nan")}
    y_true = np.asarray(y_true)
    return {"log_loss": float(log_loss(y_true, p1, labels=[0, 1])),
            "brier": float(brier_score_loss(y_true, p1, labels=[0, 1]))}


def format_score(value, digits=3):
    """A score as the tables write it: ``digits`` decimals, "n/a" for ``nan``.

    Examples
    --------
    >>> format_score(0.12345), format_score(float("nan"))
    ('0.123', 'n/a')
    """
    return NOT_AVAILABLE if value is None or np.isnan(value) else f"{value:.{digits}f}"
