"""The BSI side of the external benchmarks: screen the candidate clauses, then fit.

With a negation for every proposition (:class:`~bsi_sklearn.data.preprocessing.NegationAugmenter`)
the support of the posterior is far too large on the samples2LTL / Scarlet files;
:func:`select_roles` keeps the global candidates and subtasks whose clauses hold on the
training positives and best separate the classes, and :func:`fit_bsi` fits
:class:`~bsi_sklearn.BSIClassifier` on them. Used by ``external.py``.
"""

from __future__ import annotations

import time
import warnings

import numpy as np

from bsi_sklearn import BSIClassifier
from bsi_sklearn.data.preprocessing import NegationAugmenter

__all__ = ["NEG", "fit_bsi", "select_roles"]

NEG = "!"  # NegationAugmenter's prefix, the one Formula.to_specification reads


def _clause_stats(traces):
    """Per trace: G(p), F(p) and the first step of p (``T`` when never), every column."""
    always = np.array([t.all(axis=0) for t in traces])
    ever = np.array([t.any(axis=0) for t in traces])
    first = np.array([np.where(t.any(axis=0), t.argmax(axis=0), len(t)) for t in traces])
    return always, ever, first


def select_roles(traces, y, names, *, min_support=0.9, max_globals=6, max_subtasks=6):
    """Screen the candidate clauses of BSI on the training data and cap their number.

    With a negation for every proposition there are ``2 n`` global candidates and subtasks:
    up to 14 of each on these files, about ``10**21`` hypotheses for Prior 2, most of them
    contradictions (``G(p) & G(!p)``) that no positive satisfies. Clauses that training
    positives violate cannot raise the posterior of a specification, so only propositions
    whose clause holds on at least ``min_support`` of the training positives are kept (the
    margin leaves room for label noise):

    * global candidate ``p`` when ``G(p)`` holds on enough positives;
    * subtask ``w`` when ``F(w)`` holds on enough positives.

    Candidates are then ranked by how well their clauses separate the classes: for globals
    the positive-minus-negative rate of ``G(p)``; for subtasks the best such gap among
    ``F(w)`` and the orders ``(!b U a)`` involving ``w`` whose positive rate passes
    ``min_support``. Only the ``max_globals`` and ``max_subtasks`` best are kept (ties: plain
    propositions before negations, then name order).

    Parameters
    ----------
    traces : list of ndarray of shape (T_i, n_names), dtype bool
    y : ndarray of shape (n_traces,)
        1 for positives, 0 for negatives.
    names : list of str
        Column names.
    min_support, max_globals, max_subtasks : see above.

    Returns
    -------
    globals, subtasks : list of str
        In rank order.
    screened : dict
        Numbers of candidates that passed the screening (``"globals"``, ``"subtasks"``).

    Examples
    --------
    >>> t = np.array([[1, 0], [1, 1]], dtype=bool)      # columns p, q
    >>> u = np.array([[0, 0], [1, 0]], dtype=bool)
    >>> select_roles([t, t, u], np.array([1, 1, 0]), ["p", "q"])
    (['p'], ['q', 'p'], {'globals': 1, 'subtasks': 2})
    """
    y = np.asarray(y)
    pos, neg = y == 1, y == 0
    if not pos.any():
        return [], [], {"globals": 0, "subtasks": 0}
    always, ever, first = _clause_stats(traces)
    lengths = np.array([len(t) for t in traces])

    def rate(truth, mask):
        return float(truth[mask].mean()) if mask.any() else 0.0

    def tie(k):
        return (names[k].startswith(NEG), names[k])

    n = len(names)
    g_ok = [k for k in range(n) if rate(always[:, k], pos) >= min_support]
    g_gap = {k: rate(always[:, k], pos) - rate(always[:, k], neg) for k in g_ok}
    s_ok = [k for k in range(n) if rate(ever[:, k], pos) >= min_support]
    s_gap = {k: rate(ever[:, k], pos) - rate(ever[:, k], neg) for k in s_ok}
    for a in s_ok:
        for b in s_ok:
            if a == b:
                continue
            # (!b U a): a happens, and no b strictly before the first a
            order = (first[:, a] < lengths) & (first[:, a] <= first[:, b])
            if rate(order, pos) >= min_support:
                gap = rate(order, pos) - rate(order, neg)
                s_gap[a] = max(s_gap[a], gap)
                s_gap[b] = max(s_gap[b], gap)
    globals_ = sorted(g_ok, key=lambda k: (-g_gap[k], *tie(k)))[:max_globals]
    subtasks = sorted(s_ok, key=lambda k: (-s_gap[k], *tie(k)))[:max_subtasks]
    return ([names[k] for k in globals_], [names[k] for k in subtasks],
            {"globals": len(g_ok), "subtasks": len(s_ok)})


def fit_bsi(X_train, y_train, cfg, random_state=0):
    """Augment with negations, screen the roles, fit :class:`BSIClassifier`.

    Parameters
    ----------
    X_train : list of DataFrame
        Training traces with named boolean columns.
    y_train : ndarray
        1 / 0 labels.
    cfg : external.Config
        ``prior``, ``likelihood``, ``min_support``, ``max_globals``, ``max_subtasks``,
        ``max_exact``, ``n_samples``, ``n_chains`` are read.
    random_state : int
        Seed of the MCMC chains (unused by exact inference).

    Returns
    -------
    augmenter : NegationAugmenter
    clf : BSIClassifier
    info : dict
        ``fit_s`` (wall seconds: augmentation, screening and fit), ``globals``, ``subtasks``
        (the roles used), ``screened_*`` (candidates before the caps), ``warnings`` (the
        categories of the warnings the fit raised) and ``n_warnings`` (how many).
    """
    t0 = time.perf_counter()
    augmenter = NegationAugmenter(prefix=NEG).fit(X_train)
    Xa = augmenter.transform(X_train)
    names = [str(n) for n in augmenter.get_feature_names_out()]
    arrays = [np.asarray(x, dtype=bool) for x in Xa]
    globals_, subtasks, screened = select_roles(
        arrays, y_train, names, min_support=cfg.min_support,
        max_globals=cfg.max_globals, max_subtasks=cfg.max_subtasks)
    clf = BSIClassifier(prior=cfg.prior, likelihood=cfg.likelihood, global_candidates=globals_,
                        subtasks=subtasks, inference="auto", max_exact_hypotheses=cfg.max_exact,
                        n_samples=cfg.n_samples, n_chains=cfg.n_chains, n_jobs=1,
                        random_state=random_state)
    with warnings.catch_warnings(record=True) as caught:
        # counted per file (the "warnings" column), not printed 400 times
        warnings.simplefilter("always")
        clf.fit(Xa, y_train)
    info = {"fit_s": time.perf_counter() - t0, "globals": globals_, "subtasks": subtasks,
            "screened_globals": screened["globals"], "screened_subtasks": screened["subtasks"],
            "warnings": "; ".join(sorted({w.category.__name__ for w in caught})),
            "n_warnings": len(caught)}
    return augmenter, clf, info
