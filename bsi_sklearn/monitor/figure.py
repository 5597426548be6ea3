"""The verdicts of a monitored trace as a table, and their plot with the clause events marked."""

from __future__ import annotations

import numpy as np
import pandas as pd

from bsi_sklearn.data.traces import is_frame
from bsi_sklearn.monitor.posterior_monitor import PosteriorMonitor

__all__ = ["monitor_frame", "plot_monitor"]

_COLUMNS = ["step", "closed", "p_satisfied", "p_violated", "p_open", "events"]


def monitor_frame(posterior, trace, *, binarize=None):
    """Monitor ``trace`` step by step under ``posterior``; one row per verdict.

    Parameters
    ----------
    posterior : Posterior
    trace : array-like of shape (T, n_props) or pandas.DataFrame
        One demonstration; a DataFrame's columns must be the posterior's propositions.
    binarize : float, default=None
        As for :class:`~bsi_sklearn.monitor.posterior_monitor.PosteriorMonitor`.

    Returns
    -------
    frame : DataFrame
        Columns ``step``, ``closed``, ``p_satisfied``, ``p_violated``, ``p_open`` and
        ``events`` (the clauses that changed state, as ``"F(a) satisfied; ..."``): one row per
        step of the running trace, and a last row for the closed trace
        (:meth:`PosteriorMonitor.finish`).

    Examples
    --------
    >>> import numpy as np
    >>> from bsi_sklearn import BSIClassifier
    >>> X = [np.array([[1, 0], [1, 1]])]
    >>> clf = BSIClassifier(random_state=0).fit(X)
    >>> frame = monitor_frame(clf.posterior_, X[0])
    >>> frame[["step", "closed", "p_open"]].round(3).values.tolist()
    [[0, False, 0.96], [1, False, 0.8], [1, True, 0.0]]
    """
    mon = PosteriorMonitor(posterior, binarize=binarize)
    rows = (trace.iloc[t] for t in range(len(trace))) if is_frame(trace) else np.asarray(trace)
    verdicts = [mon.update(row) for row in rows]
    if not verdicts:
        raise ValueError("the trace has no steps")
    verdicts.append(mon.finish())
    return pd.DataFrame(
        [[v.step, v.closed, v.p_satisfied, v.p_violated, v.p_open,
          "; ".join(f"{_clause_text(e.clause)} {e.state}" for e in v.events)] for v in verdicts],
        columns=_COLUMNS,
    )


def _clause_text(key):
    if key[0] == "U":
        return f"(!{key[2]} U {key[1]})"
    return f"{key[0]}({key[1]})"


def plot_monitor(frame, ax=None, title=None):
    """Plot the three probabilities over time, with the steps where clauses changed marked.

    Parameters
    ----------
    frame : DataFrame
        From :func:`monitor_frame`.
    ax : matplotlib Axes, default=None
        Drawn on a new figure when omitted.
    title : str, default=None

    Returns
    -------
    ax : matplotlib Axes
    """
    if ax is None:
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.figure import Figure

        fig = Figure(figsize=(7.5, 3.6), layout="constrained")
        FigureCanvasAgg(fig)
        ax = fig.add_subplot()
    running = frame[~frame["closed"]]
    steps = running["step"].to_numpy()
    ax.stackplot(steps, running["p_satisfied"], running["p_open"], running["p_violated"],
                 labels=["satisfied", "open", "violated"], step="post",
                 colors=["tab:green", "0.85", "tab:red"], alpha=0.8)
    closed = frame[frame["closed"]]
    if len(closed):
        ax.plot([steps[-1] + 1], closed["p_satisfied"], "k*", markersize=10,
                label="satisfied at the end")
    for step, events in zip(running["step"], running["events"]):
        if events:
            lines = events.split("; ")
            text = "\n".join(lines[:3] + ([f"+{len(lines) - 3} more"] if len(lines) > 3 else []))
            ax.axvline(step, color="k", linewidth=0.6, linestyle=":")
            ax.annotate(text, (step, 0.5), fontsize=6, rotation=90, va="center", ha="right",
                        xytext=(-1, 0), textcoords="offset points")
    ax.set_xlim(steps[0], steps[-1] + 1.5)
    ax.set_ylim(0, 1)
    ax.set_xlabel("time step")
    ax.set_ylabel("posterior mass")
    ax.legend(fontsize=7, loc="lower left")
    if title:
        ax.set_title(title, fontsize=10)
    return ax
