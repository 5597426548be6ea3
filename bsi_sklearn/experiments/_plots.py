"""Figures of the experiments: metric means with interquartile bands against training size."""

from __future__ import annotations

from pathlib import Path

import numpy as np

__all__ = [
    "PRIOR_COLORS",
    "PRIOR_LABELS",
    "decorate",
    "new_figure",
    "plot_band",
    "priors_figure",
    "save_figure",
    "supervised_figure",
]

PRIOR_LABELS = {"linear_chain": "Prior 1", "sets_of_chains": "Prior 2", "forest": "Prior 3"}
PRIOR_COLORS = {"linear_chain": "tab:green", "sets_of_chains": "tab:blue", "forest": "tab:red"}


def new_figure(ncols=2, nrows=1, *, width=4.6, height=3.4):
    """A matplotlib Figure (Agg canvas, no pyplot state) and its array of Axes."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width * ncols, height * nrows), layout="constrained")
    FigureCanvasAgg(fig)
    axes = fig.subplots(nrows, ncols, squeeze=False)
    return fig, axes


def plot_band(ax, summary, metric, *, label, color=None, linestyle="-", marker="o",
              band=True):
    """Mean of ``metric`` against training size, with the interquartile range shaded.

    Parameters
    ----------
    ax : matplotlib Axes
    summary : DataFrame
        Rows of :func:`~bsi_sklearn.experiments._grid.aggregate` for one setting.
    metric : str
        Column stem: ``<metric>_mean``, ``<metric>_q25`` and ``<metric>_q75`` are read.
    label, color, linestyle, marker
        Line style.
    band : bool, default=True
        Shade the interquartile range.
    """
    s = summary.sort_values("size")
    x = s["size"].to_numpy(dtype=float)
    (line,) = ax.plot(x, s[f"{metric}_mean"], linestyle=linestyle, marker=marker,
                      markersize=4, color=color, label=label)
    if band:
        lo, hi = s[f"{metric}_q25"].to_numpy(float), s[f"{metric}_q75"].to_numpy(float)
        if np.any(hi > lo):
            ax.fill_between(x, lo, hi, color=line.get_color(), alpha=0.18, linewidth=0)
    return line


def save_figure(fig, path, dpi=90):
    """Save as PNG (small: these figures are committed) in one step and return the path."""
    import io

    from bsi_sklearn.io import write_atomic

    path = Path(path)
    png = io.BytesIO()
    fig.savefig(png, format="png", dpi=dpi)
    return write_atomic(path, png.getvalue())


def decorate(ax, title, ylabel):
    """Title, axis labels, grid and legend of an experiment panel."""
    ax.set_title(title, fontsize=10)
    ax.set_xlabel("positive demonstrations in the training set")
    ax.set_ylabel(ylabel)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)


def priors_figure(summary, domain, title, n_true_orders, priors=("sets_of_chains", "forest")):
    """Similarity (expected, best of top 5) and correct / extra orders of several priors.

    Parameters
    ----------
    summary : DataFrame
        Aggregated results; the positive-only CB rows of ``domain`` are drawn.
    domain : str
    title : str
        Prefix of the panel titles.
    n_true_orders : int
        Orders of the ground truth (dotted line).
    priors : sequence of str, default=("sets_of_chains", "forest")

    Returns
    -------
    fig : matplotlib Figure
    """
    rows = summary[(summary["domain"] == domain) & (summary["labels"] == "positive")
                   & (summary["likelihood"] == "cb")]
    fig, axes = new_figure(2)
    ax_sim, ax_ord = axes[0]
    for prior in priors:
        r = rows[rows["prior"] == prior]
        if r.empty:
            continue
        color, name = PRIOR_COLORS[prior], PRIOR_LABELS[prior]
        plot_band(ax_sim, r, "expected_similarity", label=f"{name} expected", color=color)
        plot_band(ax_sim, r, "best_similarity", label=f"{name} best of top 5", color=color,
                  linestyle="--", marker="s")
        plot_band(ax_ord, r, "correct_orders", label=f"{name} correct", color=color)
        plot_band(ax_ord, r, "extra_orders", label=f"{name} extra", color=color,
                  linestyle="--", marker="s")
    ax_sim.axhline(1.0, color="k", linestyle=":", linewidth=1)
    ax_ord.axhline(n_true_orders, color="k", linestyle=":", linewidth=1)
    decorate(ax_sim, f"{title}: similarity", "similarity L")
    decorate(ax_ord, f"{title}: orders (dotted: ground truth)", "expected number of orders")
    return fig


def supervised_figure(summary, domains, priors=("sets_of_chains", "forest")):
    """Positive-only against supervised fits: expected similarity and held-out accuracy.

    One column per domain; solid lines positive-only, dashed lines with negatives.

    Returns
    -------
    fig : matplotlib Figure
    """
    fig, axes = new_figure(len(domains), 2, width=4.0, height=3.0)
    for j, domain in enumerate(domains):
        for prior in priors:
            for labels, style in (("positive", "-"), ("supervised", "--")):
                r = summary[(summary["domain"] == domain) & (summary["prior"] == prior)
                            & (summary["labels"] == labels) & (summary["likelihood"] == "cb")]
                if r.empty:
                    continue
                name = f"{PRIOR_LABELS[prior]}, {labels}"
                plot_band(axes[0, j], r, "expected_similarity", label=name,
                          color=PRIOR_COLORS[prior], linestyle=style)
                plot_band(axes[1, j], r, "test_accuracy", label=name,
                          color=PRIOR_COLORS[prior], linestyle=style)
        decorate(axes[0, j], f"{domain.capitalize()}: expected L", "expected similarity")
        decorate(axes[1, j], f"{domain.capitalize()}: held-out accuracy", "accuracy")
    return fig
