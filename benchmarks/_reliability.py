"""Reliability diagrams of the benchmarks: equal-width bins of P(acceptable) and their figure.

``bench_predictive.py`` (LFE missions) and ``bench_label_noise.py`` (roles tasks, published
files, event logs) bin their pooled test predictions the same way and draw one figure per task
family into ``benchmarks/figures/reliability_<family>.png``.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

__all__ = ["N_BINS", "diagonal_axes", "draw_reliability", "reliability_bins", "worst_gap"]

#: Equal-width bins of the predicted probability.
N_BINS = 10


def reliability_bins(preds, by, n_bins=N_BINS):
    """Equal-width bins of ``preds["p"]`` per group of ``by``, every prediction pooled.

    Parameters
    ----------
    preds : DataFrame
        One line per test demonstration: the ``by`` columns, ``p`` (predicted P(label 1))
        and ``y`` (its 0/1 label).
    by : list of str
        The columns that make a curve (row, noise rate, size...).
    n_bins : int, default=N_BINS

    Returns
    -------
    bins : DataFrame
        One line per non-empty bin: the ``by`` columns, ``bin``, ``n``, ``share`` (of the
        group's predictions), ``predicted`` (mean ``p``) and ``observed`` (mean ``y``).
    """
    out = []
    for key, group in preds.groupby(by, sort=False):
        key = key if isinstance(key, tuple) else (key,)
        bins = np.minimum((group["p"].to_numpy() * n_bins).astype(int), n_bins - 1)
        for b in np.unique(bins):
            inside = group[bins == b]
            out.append(dict(zip(by, key), bin=int(b), n=len(inside),
                            share=len(inside) / len(group), predicted=inside["p"].mean(),
                            observed=inside["y"].mean()))
    return pd.DataFrame(out)


def worst_gap(bins, by, min_share=0.05):
    """Per group of ``by``: the largest |observed - predicted| over bins of ``min_share`` or more.

    Issue 31's calibration target reads the bins holding at least 5 % of the demonstrations.
    """
    big = bins[bins["share"] >= min_share]
    gap = (big["observed"] - big["predicted"]).abs()
    return big.assign(gap=gap).groupby(by, sort=False)["gap"].max()


def draw_reliability(ax, part, color, ls, label):
    """One curve on ``ax``: the bins of ``part``, marker area proportional to their share."""
    ax.plot(part["predicted"], part["observed"], ls, color=color, lw=1.2, label=label)
    ax.scatter(part["predicted"], part["observed"], s=400 * part["share"], color=color,
               alpha=0.6)


def diagonal_axes(ax, title, what="acceptable"):
    """The diagonal, the labels and the square limits of a reliability panel."""
    ax.plot([0, 1], [0, 1], color="grey", lw=0.8)
    ax.set(title=title, xlabel=f"predicted P({what})", ylabel=f"observed fraction {what}",
           xlim=(-0.02, 1.02), ylim=(-0.02, 1.02))
    ax.set_aspect("equal")
