"""Drawing the demonstrations of the synthetic and dinner-table domains."""

from __future__ import annotations

from numbers import Integral

import numpy as np

from bsi_sklearn.param_validation import Interval, validate_params

__all__ = ["plot_demos"]

# data, indices and ax are checked against each other where they are read.
_PLOT_CONSTRAINTS = {
    "n": [Interval(Integral, 1, None, closed="left")],
    "ncols": [Interval(Integral, 1, None, closed="left")],
}


def plot_demos(data, indices=None, *, n=4, ax=None, ncols=4):
    """Draw generated demonstrations, one per panel.

    For :func:`~bsi_sklearn.datasets.make_poi_threat_demos`: green discs are the POIs'
    tolerance zones (numbered; faded and marked ``x`` when a threat makes the POI
    inaccessible), red discs the threat zones of that demonstration, the path is blue for
    positives and orange (dashed) for negatives.

    For :func:`~bsi_sklearn.datasets.make_dinner_table_demos`, a top view: the table and the
    side table in grey, the centerpiece's region in red, each piece's region in green, the
    left (blue) and right (orange) wrist paths, and the pieces' final positions (black).

    Parameters
    ----------
    data : Bunch
        The output of one of the generators.
    indices : int or sequence of int, default=None
        Demonstrations to draw; by default the first ``n``.
    n : int, default=4
        Number of demonstrations when ``indices`` is None.
    ax : matplotlib Axes or array of Axes, default=None
        Where to draw (one demonstration per Axes); a new figure when None.
    ncols : int, default=4
        Panels per row of a new figure.

    Returns
    -------
    axes : ndarray of matplotlib Axes
        The Axes drawn on.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> from bsi_sklearn.datasets import make_poi_threat_demos
    >>> axes = plot_demos(make_poi_threat_demos(3, n_demos=2, random_state=0))
    >>> len(axes)
    2
    """
    import matplotlib.pyplot as plt

    validate_params({"n": n, "ncols": ncols}, _PLOT_CONSTRAINTS, "plot_demos")
    if "wrist_poses" in data:
        draw = _draw_dinner
    elif "threat_positions" in data:
        draw = _draw_poi
    else:
        raise ValueError("data is not the output of a bsi_sklearn.datasets generator")
    n_total = len(data.traces)
    if indices is None:
        indices = list(range(min(n, n_total)))
    else:
        indices = [int(i) for i in np.atleast_1d(indices)]
        for i in indices:
            if not 0 <= i < n_total:
                raise ValueError(f"indices has {i}, outside [0, {n_total})")
    if ax is None:
        ncols = min(int(ncols), len(indices))
        nrows = -(-len(indices) // ncols)
        _, axes = plt.subplots(nrows, ncols, figsize=(3.2 * ncols, 3.2 * nrows), squeeze=False)
        axes = axes.ravel()
        for extra in axes[len(indices):]:
            extra.set_axis_off()
    else:
        axes = np.atleast_1d(ax).ravel()
        if len(axes) < len(indices):
            raise ValueError(f"ax holds {len(axes)} Axes for {len(indices)} demonstrations")
    for a, i in zip(axes, indices, strict=False):
        draw(a, data, i)
        positive = bool(data.labels[i])
        a.set_title(f"demo {i}" + ("" if positive else f" (negative: {data.violations[i]})"),
                    fontsize=9)
        a.set_aspect("equal")
        a.set_xticks([])
        a.set_yticks([])
    return axes[: len(indices)]


def _draw_poi(a, data, i):
    from matplotlib.patches import Circle

    for t in data.threat_positions[i]:
        a.add_patch(Circle(t, data.threat_radius, color="tab:red", alpha=0.3, lw=0))
    for k, p in enumerate(data.poi_positions):
        ok = bool(data.accessible[i][k])
        a.add_patch(Circle(p, data.poi_radius, color="tab:green", alpha=0.7 if ok else 0.25,
                           lw=0))
        a.annotate(str(k + 1) if ok else f"{k + 1}x", p, ha="center", va="center",
                   fontsize=8)
    traj = data.trajectories[i]
    positive = bool(data.labels[i])
    a.plot(traj[:, 0], traj[:, 1], color="tab:blue" if positive else "tab:orange",
           ls="-" if positive else "--", lw=1.2)
    a.plot(*traj[0, :2], "k^", ms=5)
    a.set_xlim(0, data.world_size)
    a.set_ylim(0, data.world_size)


def _draw_dinner(a, data, i):
    from matplotlib.patches import Polygon, Rectangle

    a.add_patch(Rectangle((-0.6, -0.45), 1.2, 0.9, color="0.85", lw=0))
    a.add_patch(Rectangle((0.65, -0.5), 0.55, 0.45, color="0.9", lw=0))
    for name, tsr in data.tsrs.items():
        B = tsr.Bw
        corners = np.array([[B[0, 0], B[1, 0]], [B[0, 1], B[1, 0]], [B[0, 1], B[1, 1]],
                            [B[0, 0], B[1, 1]]])
        world = corners @ tsr.T0_w[:2, :2].T + tsr.T0_w[:2, 3]
        color = "tab:red" if name == "centerpiece" else "tab:green"
        a.add_patch(Polygon(world, closed=True, color=color, alpha=0.3, lw=0))
    wrists = data.wrist_poses[i]
    for h, color in enumerate(("tab:blue", "tab:orange")):
        a.plot(wrists[:, h, 0, 3], wrists[:, h, 1, 3], color=color, lw=0.8)
    final = data.object_poses[i][-1]
    a.plot(final[:, 0, 3], final[:, 1, 3], "k.", ms=4)
    a.set_xlim(-0.65, 1.25)
    a.set_ylim(-0.75, 0.5)
    a.set_xlabel(f"{data.meals[i]}, participant {data.participants[i]}", fontsize=8)
