"""Statistics of ``bsi-lfe study``: means with 95 % t-intervals over repeats, paired differences.

Every interval is a Student-t interval over the repeats: the repeats are independent
simulated datasets, each scored on its own test set, so their scores are independent draws and
``mean ± t(0.975, n - 1) · sd / sqrt(n)`` covers the expected score of a classifier trained on
``n_train`` missions of this simulator. The paired differences subtract, repeat by repeat, the
best network's score (and the best baseline's: the networks and the practitioner's rows) from
BSI's on the same training and test missions, and take the same interval over those
differences (a paired t-interval).
"""

from __future__ import annotations

import numpy as np
import pandas as pd
from scipy import stats

from lfe.study._cells import BSI_CV, BSI_ROWS, NETWORKS, PRACTITIONER

__all__ = ["KEYS", "LOWER_IS_BETTER", "METRICS", "paired_differences", "summarise",
           "t_interval"]

#: Columns that identify a cell of the study (besides the repeat).
KEYS = ["objective", "n_train", "noise", "propositions"]
#: Scores per run: weighted F1 over both outcomes, accuracy, and the log loss and Brier score
#: of the rows with probabilities (``nan`` for the others, and so their means and intervals).
METRICS = ("f1", "accuracy", "log_loss", "brier")
#: The metrics whose best row has the lowest mean (losses).
LOWER_IS_BETTER = frozenset({"log_loss", "brier"})


def t_interval(values, confidence=0.95):
    """Mean and Student-t confidence interval of independent values.

    Parameters
    ----------
    values : array-like of float
        One value per repeat.
    confidence : float, default=0.95

    Returns
    -------
    mean, low, high : float
        ``low`` and ``high`` are ``nan`` with fewer than two values; with no spread at all
        they equal the mean. All three are ``nan`` when a value is (a repeat without the
        score: a mean over the other repeats would not be the same cell's).
    """
    values = np.asarray(values, dtype=float)
    mean = float(values.mean())
    if len(values) < 2:
        return mean, float("nan"), float("nan")
    half = float(stats.t.ppf(0.5 + confidence / 2, len(values) - 1)
                 * values.std(ddof=1) / np.sqrt(len(values)))
    return mean, mean - half, mean + half


def summarise(runs):
    """``study.csv``: per classifier, cell and metric, the mean over repeats and its interval.

    Parameters
    ----------
    runs : DataFrame
        One row per repeat, classifier and cell (``study_runs.csv``).

    Returns
    -------
    table : DataFrame
        Columns ``classifier, objective, n_train, noise, propositions, metric, mean, ci_low,
        ci_high, n_runs``.
    """
    rows = []
    # cells written before the log loss was scored have none: those metrics are left out
    metrics = [metric for metric in METRICS if metric in runs.columns]
    for key, group in runs.groupby(["classifier", *KEYS], sort=False):
        for metric in metrics:
            mean, low, high = t_interval(group[metric])
            rows.append(dict(zip(["classifier", *KEYS], key), metric=metric, mean=mean,
                             ci_low=low, ci_high=high, n_runs=len(group)))
    return pd.DataFrame(rows)


def paired_differences(runs, metric="f1"):
    """``study_paired.csv``: each BSI row minus the best network and the best baseline.

    The best network of a cell (objective, size, noise, propositions) is the one of
    :data:`NETWORKS` with the highest mean ``metric`` over the repeats (the lowest for a
    loss, :data:`LOWER_IS_BETTER`); the best baseline, the one of the networks and the
    practitioner's rows (:data:`PRACTITIONER`, those that ran and have the score: MiniRocket
    has no log loss). Each difference is taken repeat by repeat on the same missions, then
    averaged with a paired t-interval; it is *significant* when its interval excludes 0 (for
    a loss, BSI is better when the difference is negative).

    Parameters
    ----------
    runs : DataFrame
        ``study_runs.csv``.
    metric : str, default="f1"
        A column of ``runs`` (:data:`METRICS`).

    Returns
    -------
    table : DataFrame
        Columns ``bsi, best_network, objective, n_train, noise, propositions, metric, mean,
        ci_low, ci_high, n_runs, significant`` (BSI minus the best network), then
        ``best_baseline, baseline_mean, baseline_ci_low, baseline_ci_high,
        baseline_significant`` (BSI minus the best baseline).
    """
    rows = []
    wide = runs.pivot_table(index=[*KEYS, "repeat"], columns="classifier", values=metric)
    # pivot_table drops a column with no value at all; a BSI row without any is all n/a
    wide = wide.reindex(columns=[*wide.columns,
                                 *(b for b in (*BSI_ROWS, BSI_CV) if b not in wide.columns)])
    # a row without the score (its column all missing) cannot be the best
    baselines = [name for name in (*NETWORKS, *PRACTITIONER) if name in wide.columns
                 and wide[name].notna().any()]
    networks = [name for name in NETWORKS if name in baselines]
    for key, group in wide.groupby(level=KEYS, sort=False):
        means = group[baselines].mean()
        best, best_baseline = ((means[networks].idxmin(), means.idxmin())
                               if metric in LOWER_IS_BETTER
                               else (means[networks].idxmax(), means.idxmax()))
        for bsi in (*BSI_ROWS, BSI_CV):
            mean, low, high = t_interval(group[bsi] - group[best])
            b_mean, b_low, b_high = t_interval(group[bsi] - group[best_baseline])
            rows.append(dict(bsi=bsi, best_network=best, **dict(zip(KEYS, key)), metric=metric,
                             mean=mean, ci_low=low, ci_high=high, n_runs=len(group),
                             significant=bool(low > 0 or high < 0),
                             best_baseline=best_baseline, baseline_mean=b_mean,
                             baseline_ci_low=b_low, baseline_ci_high=b_high,
                             baseline_significant=bool(b_low > 0 or b_high < 0)))
    return pd.DataFrame(rows)
